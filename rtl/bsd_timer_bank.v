// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Every event timer's front end at once, as bit vectors over the timers
// (one bit per timer and flag; timer t is the t-th pin of TIMER_MASK, so
// pins without a timer cost nothing here), and the shared tick count T. A timer holds no counter of its own: a
// measurement's reference (the start in edge mode, the pulse's beginning in
// width mode) and its end are events, queued with T as it stands after the
// event's clock (bsd_drain subtracts the two), so a timer costs a handful of
// flops and gates instead of three 16-bit registers, and every pin is still
// watched on every clock (a tick is only 3.2 clocks at 2 MHz: no scan could
// keep the +-1 tick bound). The timeout comes from bsd_timeout_wheel
// (expire_i: the timers whose 65 535th tick is the next one).
//
// Events are registered: ev_r_o (a reference), ev_f_o (a finish: a
// completion, or a timeout) and ev_any_o are of the previous clock, and t_o
// is then T including that clock's tick. Only timers whose result goes
// somewhere (HOST or RFLX) make events: one with neither is free again when
// it finishes. A timer is busy from its start until its result has been
// delivered: host_pend (cleared by host_done_i, the packet's last byte) and
// rflx_pend (cleared by rflx_done_i, its strobe).
module bsd_timer_bank #(
    parameter integer NUM_TIMERS = 4
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                tick_i,
    input  wire [NUM_TIMERS-1:0] level_i,      // the timers' pins' synchronized levels
    input  wire [NUM_TIMERS-1:0] start_i,      // PTIME_RD starts (only idle timers)
    input  wire [NUM_TIMERS-1:0] mode_i,       // each timer's pin's TMODE (1 width)
    input  wire [NUM_TIMERS-1:0] target_i,     // and TSTATE
    input  wire                host_i,       // the start's DEVCODE HOST bit
    input  wire                rflx_i,       // and its RFLX bit
    input  wire [NUM_TIMERS-1:0] expire_i,     // the next tick is these timers' timeout
    input  wire                host_done_i,  // a timer's result packet has left
    input  wire [5:0]          host_idx_i,
    input  wire                rflx_done_i,  // a timer's RFLX strobe is given
    input  wire [5:0]          rflx_idx_i,
    output wire [NUM_TIMERS-1:0] busy_o,
    output wire [NUM_TIMERS-1:0] run_o,
    output wire [NUM_TIMERS-1:0] host_pend_o,
    output wire [NUM_TIMERS-1:0] rflx_pend_o,
    output wire [NUM_TIMERS-1:0] timed_out_o,  // the measurement ended by timeout
    output wire [NUM_TIMERS-1:0] ev_r_o,
    output wire [NUM_TIMERS-1:0] ev_f_o,
    output wire                ev_any_o,
    output wire [15:0]         t_o
);
    localparam [NUM_TIMERS-1:0] ONE  = {{(NUM_TIMERS-1){1'b0}}, 1'b1};
    localparam [NUM_TIMERS-1:0] NONE = {NUM_TIMERS{1'b0}};

    reg [15:0]         t_q;
    reg [NUM_TIMERS-1:0] run_q;
    reg [NUM_TIMERS-1:0] mode_q;     // the mode and target the measurement started with
    reg [NUM_TIMERS-1:0] target_q;
    reg [NUM_TIMERS-1:0] in_pulse_q; // width mode: the pulse has begun
    reg [NUM_TIMERS-1:0] prev_q;     // the level of the previous clock
    reg [NUM_TIMERS-1:0] host_q;     // the result packet is still to leave
    reg [NUM_TIMERS-1:0] rflx_q;     // the result strobe is still to come
    reg [NUM_TIMERS-1:0] tmo_q;
    reg [NUM_TIMERS-1:0] ev_r_q, ev_f_q;
    reg                ev_any_q;

    wire [NUM_TIMERS-1:0] at       = ~(level_i ^ target_q);
    wire [NUM_TIMERS-1:0] was_at   = ~(prev_q ^ target_q);
    // Edge mode: the first clock at the target after a clock elsewhere (the
    // start clock's level is the first "previous" one); width mode: the pulse
    // began on an earlier clock and the pad has left the target.
    wire [NUM_TIMERS-1:0] complete = run_q & ((~mode_q & at & ~was_at) | (mode_q & in_pulse_q & ~at));
    wire [NUM_TIMERS-1:0] pulse_begin = run_q & mode_q & ~in_pulse_q & at & ~was_at;
    wire [NUM_TIMERS-1:0] timeout  = {NUM_TIMERS{tick_i}} & expire_i & run_q;
    wire [NUM_TIMERS-1:0] finish   = complete | timeout;
    wire [NUM_TIMERS-1:0] start    = start_i;
    wire [NUM_TIMERS-1:0] deliver  = host_q | rflx_q;
    wire [NUM_TIMERS-1:0] host_clr = host_done_i ? (ONE << host_idx_i) : NONE;
    wire [NUM_TIMERS-1:0] rflx_clr = rflx_done_i ? (ONE << rflx_idx_i) : NONE;
    wire [NUM_TIMERS-1:0] ev_r_d   = ((start & ~mode_i & {NUM_TIMERS{host_i || rflx_i}}) |
                                    (pulse_begin & deliver));
    wire [NUM_TIMERS-1:0] ev_f_d   = finish & deliver;

    assign busy_o      = run_q | host_q | rflx_q;
    assign run_o       = run_q;
    assign host_pend_o = host_q;
    assign rflx_pend_o = rflx_q;
    assign timed_out_o = tmo_q;
    assign ev_r_o      = ev_r_q;
    assign ev_f_o      = ev_f_q;
    assign ev_any_o    = ev_any_q;
    assign t_o         = t_q;

    always @(posedge clk) begin
        t_q        <= t_q + {15'd0, tick_i};
        prev_q     <= level_i;
        run_q      <= ((run_q & ~finish) | start);
        mode_q     <= ((mode_q & ~start) | (mode_i & start));
        target_q   <= ((target_q & ~start) | (target_i & start));
        in_pulse_q <= (in_pulse_q | pulse_begin) & ~start;
        host_q     <= ((host_q & ~host_clr) | (start & {NUM_TIMERS{host_i}}));
        rflx_q     <= ((rflx_q & ~rflx_clr) | (start & {NUM_TIMERS{rflx_i}}));
        // A completion on the timeout clock wins.
        tmo_q      <= (tmo_q | (timeout & ~complete)) & ~start;
        ev_r_q     <= ev_r_d;
        ev_f_q     <= ev_f_d;
        ev_any_q   <= |(ev_r_d | ev_f_d);
        if (rst) begin
            t_q        <= 16'd0;
            run_q      <= NONE;
            in_pulse_q <= NONE;
            host_q     <= NONE;
            rflx_q     <= NONE;
            tmo_q      <= NONE;
            ev_r_q     <= NONE;
            ev_f_q     <= NONE;
            ev_any_q   <= 1'b0;
        end
    end

`ifdef FORMAL
`include "bsd_timer_bank_props.vh"
`endif
endmodule
`default_nettype wire
