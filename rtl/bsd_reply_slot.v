// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The executor's reply slot and the parser's hold. The slot keeps the one
// waiting reply or message (a packet of up to 8 data bytes: bytes 4..7 only
// for cmdDEBUG's echo) for bsd_pkt_tx; rep_new_o marks the clock it fills
// (the power-up message's on the clock after reset), an event for the event
// queue, except after a cmdRESET whose flush made the packet on offer the
// power-up message (swap_i): that message is on its way already. (The
// flag, not an AND at the queue's write, which was the iCEBreaker top's
// critical path.) A DIG_IO RFLX value needs no slot: it is an event of one clock
// (dio_new_o with its ID and level) and travels in the event queue.
// The parser never completes a packet that could need the slot while it is
// full: hold_o covers the clocks after the packet up to its request (the
// packet's own clock needs no hold: the parser hands packets over at least
// two clocks apart, which its proof asserts).
//
// The reply slot takes stage 2's packet on every clock it is free, so its
// data enables never wait for the decision; the decision itself lands in a
// flop (reply_q), which is the request for one clock until the slot's own
// flag (rep_wait_q) takes over. The request thus rises when stage 2 ends,
// 3 clocks after the last byte, and comes from flops only. After reset the
// slot holds the power-up message, the first packet out.
module bsd_reply_slot (
    input  wire                clk,
    input  wire                rst,
    input  wire                pkt_valid_i,   // the parser hands a packet to the executor
    input  wire                soft_reset_i,  // stage 2 is a cmdRESET: the core resets on the next clock
    input  wire                swap_i,        // with rst: bsd_pkt_tx's packet on offer becomes the power-up message
    // the executor's stage 2 (bsd_exec)
    input  wire                s2_valid_i,    // a packet is in stage 2
    input  wire                reply_i,       // it has a reply
    input  wire [3:0]          reply_n_i,
    input  wire [31:0]         reply_data_i,
    input  wire [31:0]         reply_tail_i,  // its data bytes 4..7
    input  wire                dio_rflx_i,    // it sends a DIG_IO value on RFLX
    input  wire [5:0]          dio_id_i,
    input  wire                dio_val_i,
    // to the parser: a packet that may need a slot must wait (a flop, so the
    // parser's s_axis_tready starts at flops: it was the iCEBreaker top's
    // critical path behind an OR with pkt_valid_i)
    output wire                hold_o,
    // the waiting reply, to bsd_pkt_tx: A, rep_n_o, rep_data_o[31:24] .. rep_tail_o[7:0]
    output wire                rep_req_o,
    output wire [3:0]          rep_n_o,
    output wire [31:0]         rep_data_o,
    output wire [31:0]         rep_tail_o,
    input  wire                rep_done_i,
    output wire                rep_new_o,     // the reply slot has filled (an event)
    // a DIG_IO RFLX value, to the event queue
    output wire                dio_new_o,     // a DIG_IO RFLX value (an event, one clock)
    output wire [5:0]          dio_id_o,
    output wire                dio_val_o
);
    `include "bsd_protocol.vh"

    reg                reply_q;      // stage 2 chose a reply on the last clock
    reg                rep_wait_q;   // the reply slot is full
    reg [3:0]          rep_n_q;
    reg [31:0]         rep_data_q;
    reg [31:0]         rep_tail_q;
    reg [5:0]          dio_id_q;
    reg                dio_val_q;
    reg                dio_new_q;
    reg                new_q;        // the slot has filled: reply_q, or the clock after reset
                                     // (the power-up message's event, unless swap_i), as one flop
    reg                pending_q;    // see hold_o

    assign rep_req_o   = reply_q || rep_wait_q;
    assign rep_n_o     = rep_n_q;
    assign rep_data_o  = rep_data_q;
    assign rep_tail_o  = rep_tail_q;
    assign dio_id_o    = dio_id_q;
    assign dio_val_o   = dio_val_q;
    assign rep_new_o   = new_q;
    assign dio_new_o   = dio_new_q;

    // hold_o: the slot is full, or a packet is in stage 2 and may fill it,
    // or the core resets (the clock after soft_reset_i, when the reset fills
    // the slot with the power-up message): worked out a clock ahead, from each
    // flag's next value, so that it is a flop.
    wire rep_wait_d = rep_req_o && !rep_done_i;
    assign hold_o = pending_q;

    always @(posedge clk) begin
        reply_q    <= reply_i;
        rep_wait_q <= rep_wait_d;
        pending_q  <= pkt_valid_i || reply_i || rep_wait_d || soft_reset_i;
        if (s2_valid_i && !rep_req_o) begin
            rep_n_q    <= reply_n_i;
            rep_data_q <= reply_data_i;
            rep_tail_q <= reply_tail_i;
        end
        dio_new_q <= dio_rflx_i;
        new_q     <= reply_i;
        if (dio_rflx_i) begin
            dio_id_q    <= dio_id_i;
            dio_val_q   <= dio_val_i;
        end
        if (rst) begin
            // The power-up message is the first packet out.
            reply_q     <= 1'b0;
            rep_wait_q  <= 1'b1;  // the power-up message waits
            pending_q   <= 1'b1;
            rep_n_q     <= 4'd2;
            rep_data_q  <= {CMD_MSG, MSG_STATE_POWER_RESET, 16'd0};
            rep_tail_q  <= 32'd0;
            dio_id_q    <= 6'd0;
            dio_val_q   <= 1'b0;
            dio_new_q   <= 1'b0;
            new_q       <= !swap_i;
        end
    end

`ifdef FORMAL
`include "bsd_reply_slot_props.vh"
`endif
endmodule
`default_nettype wire
