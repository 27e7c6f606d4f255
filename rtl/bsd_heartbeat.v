// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// cmdHB: queues an UP/DOWN heartbeat (alternately) every HB_RATE x 25.6 ms
// and tracks the host's answers. link_up rises on an answer to the latest
// heartbeat and falls when a heartbeat falls due while the previous one is
// unanswered (or not even sent: that due heartbeat is then skipped).
module bsd_heartbeat #(
    parameter integer HB_RATE = 0
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       tick_i,
    input  wire       answer_i,       // a host cmdHB answer (N >= 2, type UP or DOWN + 2)
    input  wire       answer_down_i,  // it answers a DOWN heartbeat
    output wire       req_o,          // a heartbeat packet waits to be sent
    output wire       new_o,          // one is queued now (req_o rises on the next clock)
    // Bits 7:1 are constant 0; bit 0 is down_q, whose toggles count there.
    /* verilator coverage_off */
    output wire [7:0] type_o,         // its type byte
    /* verilator coverage_on */
    input  wire       done_i,         // it has left
    output wire       link_up_o
);
    `include "bsd_protocol.vh"

    // HB_RATE = 0: no heartbeat ever falls due, so link_up stays 0.
    localparam integer PERIOD = (HB_RATE == 0 ? 1 : HB_RATE) * HB_UNIT_TICKS;
    localparam integer W      = $clog2(PERIOD);
    localparam integer LAST_BEFORE = PERIOD - 2;  // PERIOD >= 16 000

    reg [W-1:0] ticks_q;
    reg         at_end_q;    // ticks_q == PERIOD - 1: the next tick makes a heartbeat due
    reg         down_q;      // type of the latest heartbeat: 0 UP, 1 DOWN
    reg         queued_q;    // a heartbeat has been queued since reset
    reg         answered_q;  // the latest one is answered
    reg         req_q;       // a heartbeat packet waits to be sent
    reg         link_up_q;

    wire due      = (HB_RATE != 0) && tick_i && at_end_q;
    // The answer must match the latest heartbeat's type.
    wire answer   = answer_i && queued_q && answer_down_i == down_q;
    wire answered = answered_q || answer;

    assign req_o     = req_q;
    assign new_o     = due && !req_q;
    assign type_o    = {7'd0, down_q};
    assign link_up_o = link_up_q;

    always @(posedge clk) begin
        if (tick_i) begin
            ticks_q  <= due ? {W{1'b0}} : ticks_q + 1'b1;
            // From the register, not the sum: the comparator stays off `due`.
            at_end_q <= !due && ticks_q == LAST_BEFORE[W-1:0];
        end
        if (done_i) req_q <= 1'b0;
        // (nested under answer_i, the rare term: a simulator tests one bit on most clocks)
        if (answer_i) begin
            if (answer) begin
                answered_q <= 1'b1;
                link_up_q  <= 1'b1;
            end
        end
        if (due) begin
            if (!answered || req_q) link_up_q <= 1'b0;
            if (!req_q) begin
                req_q      <= 1'b1;
                down_q     <= queued_q ? !down_q : 1'b0;
                queued_q   <= 1'b1;
                answered_q <= 1'b0;
            end
        end
        if (rst) begin
            ticks_q    <= {W{1'b0}};
            at_end_q   <= 1'b0;
            req_q      <= 1'b0;
            down_q     <= 1'b0;
            queued_q   <= 1'b0;
            answered_q <= 1'b0;
            link_up_q  <= 1'b0;
        end
    end

`ifdef FORMAL
`include "bsd_heartbeat_props.vh"
`endif
endmodule
`default_nettype wire
