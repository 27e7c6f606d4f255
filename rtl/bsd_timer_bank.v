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
// Events are registered: ev_r_o (a reference), ev_f_o (a completion) and
// both bits together (a timeout, which needs no reference: its result is 0),
// and ev_any_o are of the previous clock, and t_o is then T including that
// clock's tick. So the drain learns a timeout from the event itself and no
// timer keeps a timed-out flag. Only timers whose result goes
// somewhere (HOST or RFLX) make events: one with neither is free again when
// it finishes. A timer is busy from its start until its result has been
// delivered: one flag per timer (pend, result owed) is cleared by
// host_done_i (the packet's last byte) or rflx_done_i (the strobe of a
// result without HOST: bsd_drain names only those, as with both bits the
// strobe always comes before the packet's last byte). So one flag and one
// gate on two 8-way decodes per timer replace a flag and a 64-way decoder
// per delivery; the run's HOST and RFLX bits (run_host_o, run_rflx_o, read
// by the drain at a finish) are only loaded at a start (a flop with an
// enable, no gate). From 17 timers on the top leaves them unread and
// synthesis drops them: bsd_drain keeps the bits in a memory (a flop that
// loads with an enable and no gate takes an iCE40 logic cell alone).
//
// Width mode is edge mode twice: a pulse's beginning is an edge to the
// target, after which the target is inverted, so its end is an edge to the
// new target. One flag (pulse still to begin) replaces the mode and a
// pulse-begun flag, and one edge detector serves both modes.
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
    output wire [NUM_TIMERS-1:0] run_host_o,   // the HOST and RFLX bits of each timer's
    output wire [NUM_TIMERS-1:0] run_rflx_o,   // last start (valid from it on)
    output wire [NUM_TIMERS-1:0] ev_r_o,
    output wire [NUM_TIMERS-1:0] ev_f_o,
    output wire                ev_any_o,
    output wire [15:0]         t_o
);
    localparam [NUM_TIMERS-1:0] NONE = {NUM_TIMERS{1'b0}};

    reg [15:0]         t_q;
    reg [NUM_TIMERS-1:0] run_q;
    reg [NUM_TIMERS-1:0] target_q;   // the level waited for (inverted as a pulse begins)
    reg [NUM_TIMERS-1:0] wait_pb_q;  // width mode: the pulse is still to begin
    reg [NUM_TIMERS-1:0] prev_q;     // the level of the previous clock
    reg [NUM_TIMERS-1:0] pend_q;     // the result is still to be delivered (HOST or RFLX)
    reg [NUM_TIMERS-1:0] host_q;     // the last start's HOST bit
    reg [NUM_TIMERS-1:0] rflx_q;     // and its RFLX bit
    reg [NUM_TIMERS-1:0] ev_r_q, ev_f_q;
    reg                ev_any_q;  // (built only with up to ANY_FLOP_MAX timers)

    // The first clock at the target after a clock elsewhere (the start
    // clock's level is the first "previous" one).
    wire [NUM_TIMERS-1:0] edge_at  = run_q & ~(level_i ^ target_q) & (prev_q ^ target_q);
    wire [NUM_TIMERS-1:0] complete = edge_at & ~wait_pb_q;
    wire [NUM_TIMERS-1:0] pulse_begin = edge_at & wait_pb_q;
    wire [NUM_TIMERS-1:0] timeout  = {NUM_TIMERS{tick_i}} & expire_i & run_q;
    wire [NUM_TIMERS-1:0] finish   = complete | timeout;
    wire [NUM_TIMERS-1:0] start    = start_i;
    // pend_q is set only by a start with HOST or RFLX and cleared only after
    // the run has ended, so while a timer runs it says whether it delivers.
    wire [NUM_TIMERS-1:0] deliver  = pend_q;
    // The two deliveries' clears, ORed per timer.
    wire [NUM_TIMERS-1:0] host_clr, rflx_clr;
    bsd_idx_onehot #(.N(NUM_TIMERS)) u_host_clr (.en_i(host_done_i), .idx_i(host_idx_i), .onehot_o(host_clr));
    bsd_idx_onehot #(.N(NUM_TIMERS)) u_rflx_clr (.en_i(rflx_done_i), .idx_i(rflx_idx_i), .onehot_o(rflx_clr));
    wire [NUM_TIMERS-1:0] clr = host_clr | rflx_clr;
    // A completion on the timeout clock wins; a pulse that begins on it has
    // no result (a timeout's event is r and f together).
    wire [NUM_TIMERS-1:0] ev_r_d   = ((start & ~mode_i & {NUM_TIMERS{host_i || rflx_i}}) |
                                    (deliver & (pulse_begin | (timeout & ~complete))));
    wire [NUM_TIMERS-1:0] ev_f_d   = finish & deliver;

    assign busy_o      = run_q | pend_q;
    assign run_o       = run_q;
    assign run_host_o  = host_q;
    assign run_rflx_o  = rflx_q;
    assign ev_r_o      = ev_r_q;
    assign ev_f_o      = ev_f_q;
    // Many timers: an OR over the event flops, not a flop of its own loaded
    // from an OR over their next values: that OR took the output of each
    // event bit's last LUT, and nextpnr gives a flop whose D LUT feeds
    // anything else a logic cell of its own (128 cells at 64 timers, for the
    // same OR tree). A few timers: the flop, whose OR costs a few cells but
    // keeps a LUT level off the event queue's write and the drain's input
    // (GP 1.0's board top: median Fmax 54.2 MHz with the OR, 56.0 without).
    localparam integer ANY_FLOP_MAX = 8;
    assign ev_any_o    = NUM_TIMERS <= ANY_FLOP_MAX ? ev_any_q : |(ev_r_q | ev_f_q);
    assign t_o         = t_q;

    // A flop with an enable per timer (the start), no gate: a mux per bit,
    // so that synthesis sees the enable; simulated only on a start's clock.
    integer b;
    always @(posedge clk) begin
        if (|start) begin
            for (b = 0; b < NUM_TIMERS; b = b + 1) begin
                if (start[b]) begin
                    host_q[b] <= host_i;
                    rflx_q[b] <= rflx_i;
                end
            end
        end
    end

    always @(posedge clk) begin
        t_q        <= t_q + {15'd0, tick_i};
        prev_q     <= level_i;
        run_q      <= ((run_q & ~finish) | start);
        target_q   <= ((target_q ^ pulse_begin) & ~start) | (target_i & start);
        wait_pb_q  <= ((wait_pb_q & ~pulse_begin) & ~start) | (mode_i & start);
        // The deliveries' decoders only on a delivery's clock (clr is zero on the others), so
        // that a simulator works them out only then.
        pend_q     <= ((host_done_i || rflx_done_i) ? pend_q & ~clr : pend_q) |
                      (start & {NUM_TIMERS{host_i || rflx_i}});
        ev_r_q     <= ev_r_d;
        ev_f_q     <= ev_f_d;
        // (ev_r_d | ev_f_d simplified by hand, pulse_begin | complete being edge_at: synthesis
        // keeps ev_r_d's terms apart and takes a LUT level more)
        if (NUM_TIMERS <= ANY_FLOP_MAX)
            ev_any_q <= |((start & ~mode_i & {NUM_TIMERS{host_i || rflx_i}}) | (deliver & (edge_at | timeout)));
        if (rst) begin
            t_q        <= 16'd0;
            run_q      <= NONE;
            pend_q     <= NONE;
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
