// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// One pin's logic event timer (cmdPTIME_RD).
// Edge mode counts ticks from the start until the pin goes non-target ->
// target; width mode waits for that edge, then counts until the pin returns
// to non-target. Counts are the tick strobes after the reference clock up to
// and including the completing clock. 65 535 ticks after the start without
// completion is a timeout, reported as 0; a completed result is at least 1.
// The result is held, and the timer stays busy, until every requested
// delivery (host packet, RFLX strobe) is done. While the timer runs,
// result_o is not meaningful (it follows the count); it is from the clock
// the measurement ends, when the requests rise.
module bsd_event_timer (
    input  wire        clk,
    input  wire        rst,
    input  wire        tick_i,
    input  wire        level_i,      // synchronized pad level, sampled every clock
    input  wire        start_i,
    input  wire        mode_i,       // TMODE: 0 edge, 1 width
    input  wire        target_i,     // TSTATE
    input  wire        host_i,       // send the result as cmdDEV_VAL
    input  wire        rflx_i,       // strobe the result on rflx_*
    input  wire        host_done_i,  // the result's packet has left
    input  wire        rflx_done_i,  // the result's RFLX strobe is given
    output wire        busy_o,
    output wire        host_req_o,
    output wire        rflx_req_o,
    output wire [15:0] result_o
);
    localparam [15:0] TIMEOUT_TICKS = 16'hFFFF;
    localparam [15:0] LAST_BEFORE   = TIMEOUT_TICKS - 16'd1;  // 65 534

    reg        running_q;
    reg        mode_q;
    reg        target_q;
    reg        host_q;
    reg        rflx_q;
    reg        prev_q;
    reg        in_pulse_q;    // width mode: the target level has begun
    reg [15:0] elapsed_q;     // ticks since the start, for the timeout
    reg [15:0] count_q;       // ticks of the measured interval
    // The completion test, prepared a clock ahead so that finishing reads a
    // few flops and the pad level instead of comparators and mode muxes.
    // armed_q and at_last_q matter only while running_q, so they are worked
    // out on every clock, the start decision not among their inputs: an idle
    // clock loads what a start needs.
    reg        armed_q;       // a pad level of want_q completes now
    reg        want_q;        // edge mode: TSTATE; width mode: its opposite
    reg        at_last_q;     // elapsed_q == 65 534: the next tick times out
    reg        count_zero_q;  // count_q == 0
    reg        host_req_q;    // the result's host packet is requested
    reg        rflx_req_q;    // the result's RFLX strobe is requested
    reg [15:0] result_q;

    wire        at_target   = level_i == target_q;
    wire        pulse_begin = mode_q && !in_pulse_q && (prev_q != target_q) && at_target;
    wire [15:0] elapsed_inc = elapsed_q + {15'd0, tick_i};
    wire [15:0] count_inc   = count_q + {15'd0, tick_i};
    wire        complete    = running_q && armed_q && (level_i == want_q);
    // Flags instead of the adders' sums keep the carry chains off the
    // enables: elapsed_inc reaches 65 535 exactly when a tick comes at 65 534,
    // and count_inc is 0 exactly when count_q is 0 and no tick comes (the
    // counts stop below 65 535, so neither wraps).
    wire        timeout     = running_q && tick_i && at_last_q;
    wire        count_zero  = !tick_i && count_zero_q;
    wire        finish      = complete || timeout;

    assign busy_o     = running_q || host_req_q || rflx_req_q;
    assign host_req_o = host_req_q;
    assign rflx_req_o = rflx_req_q;
    assign result_o   = result_q;

    // A start needs an idle timer (not running), so the start and running
    // branches below never meet; they are written apart so that finishing
    // does not wait for the start decision.
    always @(posedge clk) begin
        // Edge mode completes on the first clock the pad reaches the target
        // from elsewhere; width mode first waits for that edge (it has begun
        // when the pad is at the target after being elsewhere), then
        // completes when the pad leaves the target.
        armed_q   <= running_q ? (mode_q ? at_target && (in_pulse_q || prev_q != target_q) : !at_target)
                               : !mode_i && (level_i != target_i);
        // elapsed_q moves only on a tick: compare the register, not the sum.
        at_last_q <= running_q && (tick_i ? elapsed_q == LAST_BEFORE - 16'd1 : at_last_q);
        if (start_i && !busy_o) begin
            running_q    <= 1'b1;
            mode_q       <= mode_i;
            target_q     <= target_i;
            host_q       <= host_i;
            rflx_q       <= rflx_i;
            prev_q       <= level_i;
            in_pulse_q   <= 1'b0;
            elapsed_q    <= 16'd0;
            count_q      <= 16'd0;
            want_q       <= mode_i ? !target_i : target_i;
            count_zero_q <= 1'b1;
        end
        if (running_q) begin
            prev_q       <= level_i;
            elapsed_q    <= elapsed_inc;
            count_q      <= pulse_begin ? 16'd0 : count_inc;
            count_zero_q <= pulse_begin || count_zero;
            if (pulse_begin) in_pulse_q <= 1'b1;
            // The result as it would be if the measurement ended now; the
            // clock it ends keeps it. Written on every running clock, so its
            // 16 enables are running_q, not the completion logic.
            result_q     <= !complete ? 16'd0 : count_zero ? 16'd1 : count_inc;
        end
        if (finish) begin
            running_q  <= 1'b0;
            host_req_q <= host_q;
            rflx_req_q <= rflx_q;
        end
        if (host_done_i) host_req_q <= 1'b0;
        if (rflx_done_i) rflx_req_q <= 1'b0;
        if (rst) begin
            running_q  <= 1'b0;
            host_req_q <= 1'b0;
            rflx_req_q <= 1'b0;
            result_q   <= 16'd0;
        end
    end

`ifdef FORMAL
`include "bsd_event_timer_props.vh"
`endif
endmodule
`default_nettype wire
