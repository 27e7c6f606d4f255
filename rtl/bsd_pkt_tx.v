// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Sends whole packets `A, N, d0..` onto m_axis in the order of the output
// queue (bsd_drain fills it in event order). An item names its packet
// instead of carrying it: a timer result (the timer and its 16-bit value),
// the command reply (its bytes wait in bsd_reply_slot) or the heartbeat
// (its type waits in bsd_heartbeat). So there is no K-way packet mux and no
// arbiter: the head item is taken on the clock of the previous packet's
// last handshake (packets leave back to back), and m_axis_tdata is a
// register, loaded with the next byte (picked by a flag per byte) on each
// handshake. When a packet's last byte
// leaves, its source is told (timer_done_o with its index, reply_done_o,
// hb_done_o): a timer is busy, and the reply slot full, until then.
//
// flush_i (cmdRESET, while the sources and the queue are reset around it):
// no item is taken; a packet with a byte already taken is finished, so the
// host's framing holds, and credits nobody. One whose first byte is offered
// but not yet taken cannot be withdrawn (AXI-Stream), but every packet starts
// with the address, so it becomes the power-up message in place, credited to
// the reply slot (which holds that message after the reset); swap_o tells
// the reply slot on that clock, so that the message it holds after the reset
// makes no event of its own (it would be queued again).
module bsd_pkt_tx #(
    parameter integer MODULE_ADDR = 2
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        flush_i,      // cmdRESET
    output wire        swap_o,       // this clock's flush makes the packet on offer the power-up message
    // the output queue's head: {kind, timer, its device ID, result}
    input  wire        item_valid_i,
    input  wire [29:0] item_data_i,
    output wire        item_ready_o,
    output wire        free_o,       // an item offered now would be taken (but for flush_i)
    output wire        idle_o,       // no packet going out (from flops only)
    // the reply slot: A, rep_n_i, rep_data_i[31:24] .. rep_tail_i[7:0]
    input  wire [3:0]  rep_n_i,
    input  wire [31:0] rep_data_i,
    input  wire [31:0] rep_tail_i,
    // Bits 7:1 are constant 0 (bsd_heartbeat); bit 0 counts in byte_hb and the heartbeat's down_q.
    /* verilator coverage_off */
    input  wire [7:0]  hb_type_i,
    /* verilator coverage_on */
    output wire        timer_done_o,
    output wire [5:0]  timer_idx_o,
    output wire        reply_done_o,
    output wire        hb_done_o,
    output wire [7:0]  m_axis_tdata,
    output wire        m_axis_tvalid,
    input  wire        m_axis_tready,
    output wire        m_axis_tlast
);
    `include "bsd_protocol.vh"

    // An item's kind (bsd_drain's KIND_*): 0 a timer result, 1 the reply, 2 the heartbeat.
    localparam [1:0] KIND_REPLY = 2'd1;
    localparam [7:0] ADDR_OWN   = MODULE_ADDR[7:0];

    // The packet going out: its source and the byte offered. The bytes are
    // picked from where they wait (the reply slot, the heartbeat, the result
    // held here) by a byte index, so nothing is copied into a shift register.
    reg        valid_q;
    reg        last_q;   // the byte offered is the packet's last
    // N minus the byte offered (0 the address, 1 N, 2.. data): N itself while the
    // address is offered (the next byte), and 0 on the byte before the last.
    reg [3:0]  rem_q;
    reg [1:0]  kind_q;
    reg [5:0]  idx_q;
    reg [5:0]  id_q;
    reg [15:0] result_q;
    reg        first_q;   // no byte of it taken yet
    // The heartbeat's type, copied as the packet starts: a cmdRESET resets the
    // heartbeat while its packet may still be going out. The reply's bytes are
    // read from the reply slot as they go: the slot keeps them until the last
    // byte has left, and a cmdRESET never meets a reply on its way (it waits
    // while a reply waits, decision 14); after one, the slot holds the
    // power-up message, which is what a swapped packet sends.
    // Only bit 0 of the type is ever 1 (it counts in byte_hb): the rest stay out of coverage.
    /* verilator coverage_off */
    reg [7:0]  hb_type_q;
    /* verilator coverage_on */
    reg        credit_q;  // its source is told when it has left (not after a cmdRESET)

    wire       hs   = valid_q && m_axis_tready;
    wire       free = !flush_i && free_o;
    wire       load = item_valid_i && free;
    wire       swap = flush_i && valid_q && first_q && !m_axis_tready;
    // The byte registers move on every handshake and whenever an item is offered
    // while idle (step): from a flop, the handshake and the item's valid, not
    // from load (which waits for last_q and the flush as well). In a packet, not
    // after its last byte (mid), a step offers the next byte; otherwise it starts
    // one with the item offered, which is taken then unless this is a last byte
    // with nothing offered or a flush: valid_q then stays or falls to 0, and what
    // was loaded is never read.
    wire       step = valid_q ? m_axis_tready : item_valid_i;
    wire       mid  = valid_q && !last_q;
    wire [1:0] kind = item_data_i[29:28];
    // The kinds are 0, 1 and 2 (never 3): bit 0 alone marks a reply, bit 1
    // alone a heartbeat, so each test is one bit (a timer's: neither).
    wire [3:0] n    = kind[0] ? rep_n_i : kind[1] ? 4'd2 : 4'd4;
    wire       k_timer = !kind_q[0] && !kind_q[1];
    wire       k_reply = kind_q[0];
    wire       k_hb    = kind_q[1];

    // The byte on offer sits in a register (tdata_q), written as the packet
    // starts (the address) and on each handshake (the next byte), so a
    // simulator works the byte out once per byte, not every clock. The next
    // byte is picked by one-hot flags, one per byte of each source (the kind
    // folded in), that mark the byte offered now: an AND-OR of a few terms
    // instead of a mux on a byte index and kind_q. The flags advance with
    // rem_q (which still counts for tlast).
    reg        sel_addr_q, sel_n_q;
    reg        sel_tcmd_q, sel_tid_q, sel_thi_q;  // a timer result's d0..d2 (d3 is last)
    reg [6:0]  sel_rep_q;                         // the reply's d0..d6 (d7 is last)
    reg        sel_hcmd_q;                        // the heartbeat's d0 (d1 is last)
    reg [7:0]  tdata_q;
    function [7:0] when(input s, input [7:0] b);
        begin
            when = {8{s}} & b;
        end
    endfunction
    // The reply byte after the one offered: d0 after N, d(j+1) after dj.
    function [7:0] rep_next(input n_now, input [6:0] sel, input [63:0] bytes);
        integer j;
        begin
            rep_next = when(n_now, bytes[63:56]);
            for (j = 0; j < 7; j = j + 1) rep_next = rep_next | when(sel[j], bytes[55-8*j -: 8]);
        end
    endfunction
    wire [63:0] rep_bytes = {rep_data_i, rep_tail_i};

    wire done = hs && last_q && credit_q;
    assign item_ready_o  = load;
    // (no flush_i: the output queue, its only reader, is reset with it, and its
    // read enable, which free_o reaches, waits for one flop less)
    assign free_o        = !valid_q || (hs && last_q);
    assign idle_o        = !valid_q;
    assign swap_o        = swap && !rst;
    assign timer_done_o  = done && k_timer;
    assign timer_idx_o   = idx_q;
    assign reply_done_o  = done && k_reply;
    assign hb_done_o     = done && k_hb;
    assign m_axis_tdata  = tdata_q;
    assign m_axis_tvalid = valid_q;
    assign m_axis_tlast  = last_q;

    always @(posedge clk) begin
        // valid_q, last_q and credit_q take their next values as one expression
        // each (no enable), written without load: its terms that only matter
        // in a packet's last clock are folded into the flops' own terms.
        // (valid_q: load is an item offered, no flush, when idle or on a last handshake)
        valid_q <= !rst && ((item_valid_i && !flush_i) || (valid_q && !(m_axis_tready && last_q)));
        // The next byte is d(N-1) when rem_q reaches 0. A packet is at least A, N, so
        // its first byte is never its last (a swap keeps last_q 0); idle, last_q is 0.
        last_q  <= !rst && valid_q && (m_axis_tready ? !last_q && rem_q == 4'd0 : last_q);
        // A flush without a swap: finished, credited to nobody. Set whenever no packet
        // goes on and on a last handshake, so that a packet starts credited.
        credit_q <= !rst && (!valid_q || (m_axis_tready && last_q) || (credit_q && !(flush_i && !swap)));
        // The packet's registers are written only on a step: on an idle clock (nothing
        // offered) valid_q stays 0 and they are never read, so a simulator skips them
        // there (most clocks of a busy session).
        if (step) begin
            if (mid) begin
                // (the address's byte, then by kind: a simulator works out only the
                // packet's own source's terms; the flags of the other kinds are 0)
                if (sel_addr_q)
                    tdata_q <= {4'd0, rem_q};
                else if (k_reply)
                    tdata_q <= rep_next(sel_n_q, sel_rep_q, rep_bytes);
                else if (k_hb)
                    tdata_q <= when(sel_n_q, CMD_HB) | when(sel_hcmd_q, hb_type_q);
                else
                    tdata_q <= when(sel_n_q, CMD_DEV_VAL) | when(sel_tcmd_q, {2'b00, id_q}) |
                               when(sel_tid_q, result_q[15:8]) | when(sel_thi_q, result_q[7:0]);
                // The next byte's flag (none after a packet's last byte: a reply
                // has N <= 8, PROTOCOL.md).
                // (from the chain's end back: each flag is read before it is written)
                sel_hcmd_q  <= sel_n_q && k_hb;
                sel_rep_q   <= {sel_rep_q[5:0], sel_n_q && k_reply};
                sel_thi_q   <= sel_tid_q;
                sel_tid_q   <= sel_tcmd_q;
                sel_tcmd_q  <= sel_n_q && k_timer;
                sel_n_q     <= sel_addr_q;
                sel_addr_q  <= 1'b0;
                rem_q   <= rem_q - 4'd1;
                first_q <= 1'b0;
            end else begin
                rem_q    <= n;
                kind_q   <= kind;
                idx_q    <= item_data_i[27:22];
                first_q  <= 1'b1;
                hb_type_q  <= hb_type_i;
                id_q     <= item_data_i[21:16];
                result_q <= item_data_i[15:0];
                {sel_addr_q, sel_n_q, sel_tcmd_q, sel_tid_q, sel_thi_q} <= 5'b10000;
                {sel_rep_q, sel_hcmd_q} <= 8'd0;
                tdata_q  <= ADDR_OWN;
            end
        end
        if (swap) begin
            // The address is on offer already; the rest becomes `2, 0x80, 4`,
            // which the reply slot holds from the next clock.
            kind_q     <= KIND_REPLY;
            rem_q      <= MSG_N[3:0];
        end
        // (the byte registers need no reset: read only while valid_q, and a packet
        // starts them; the outputs' do, for a simulator's sake)
        if (rst) begin
            idx_q   <= 6'd0;
            tdata_q <= ADDR_OWN;
        end
    end

`ifdef FORMAL
`include "bsd_pkt_tx_props.vh"
`endif
endmodule
`default_nettype wire
