// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Byte framing of host packets: address, N, d0 .. d(N-1). Hands each
// complete packet that needs action to the executor as a one-clock pulse with
// N and its data bytes (d0..d2 for the commands, d3..d7 for cmdDEBUG's echo),
// d0 decoded into one flag per command the executor knows (pkt_cmd_o), and
// d1's pin as a one-hot over the pins (pkt_sel_o), each worked out as its
// byte arrives so that the executor's decisions start from flops. A
// packet's own bytes d0..d(N-1), and pkt_sel_o with N >= 2, hold on the
// clock after its pulse as well (the executor's second stage reads them).
// Slot N follows the stream until the next N byte and the slots past it
// keep older bytes: none of them means anything (after a one-byte packet,
// pkt_d1_o and pkt_sel_o).
// Packets for other addresses are consumed silently; N > 8 resyncs on the
// next byte; a partial packet is dropped after RX_TIMEOUT_US of waiting for a
// byte.
module bsd_parser #(
    parameter integer MODULE_ADDR   = 2,
    parameter integer RX_TIMEOUT_US = 25_600,
    parameter integer NUM_PINS      = 5    // the width of pkt_sel_o
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       tick_i,        // 1.6 us strobe
    input  wire       hold_i,        // a reply is waiting: hold packets that may need another
    input  wire [7:0] s_axis_tdata,
    input  wire       s_axis_tvalid,
    output wire       s_axis_tready,
    output wire       pkt_valid_o,
    output wire [1:0] pkt_kind_o,
    output wire [3:0] pkt_n_o,
    output wire [7:0] pkt_d0_o,
    // d0 is: bit CMDF_<NAME> (bsd_protocol.vh) cmd<NAME>, bit CMDF_ANY any of these
    output wire [7:0] pkt_cmd_o,
    output wire [7:0] pkt_d1_o,
    output wire [NUM_PINS-1:0] pkt_sel_o,  // d1's bits 5:0 as a one-hot over the pins (0 past the last)
    output wire [7:0] pkt_d2_o,
    output wire [39:0] pkt_tail_o    // d3..d7, d3 in the top byte (cmdDEBUG echoes them)
);
    `include "bsd_protocol.vh"

    localparam [7:0] ADDR_OWN = MODULE_ADDR[7:0];
    localparam [NUM_PINS-1:0] SEL_ONE = 1;

    // Idle ticks that drop a partial packet: one more than ceil(US / 1.6),
    // so the drop never comes before RX_TIMEOUT_US whatever the tick phase.
    localparam integer TIMEOUT_TICKS = (RX_TIMEOUT_US * 5 + 7) / 8 + 1;

    // The idle ticks are counted by a Galois LFSR (no adder: a flop a bit and
    // one XOR): it starts at 1 and steps by a multiplication by x modulo
    // a primitive polynomial of degree LW, so after k idle ticks it holds
    // x^k mod the polynomial, distinct for k < 2^LW - 1. IDLE_END, the value
    // after TIMEOUT_TICKS - 1 ticks, marks that the next idle tick drops.
    `include "bsd_lfsr.vh"
    localparam integer    LW       = lfsr_width(TIMEOUT_TICKS);
    localparam [31:0]     LFSR_P   = lfsr_poly(LW);
    localparam [31:0]     IDLE_POW = lfsr_pow(TIMEOUT_TICKS - 1, LW, LFSR_P);
    localparam [LW-1:0]   IDLE_END = IDLE_POW[LW-1:0];

    // ------------------------------------------------------------ registers
    // The state, one flag each (none set: waiting for an address), as the bits
    // of one register loaded whole from next_state(): a simulator stores one
    // field of the function's value, not a field cut out for each flag, and
    // keeps one copy of the register (it is read after that write), not one
    // of each flag. (The wires are the flags' names.)
    reg  [3:0]    state_q;
    wire          len_q       = state_q[3];  // the next byte is N
    wire          data_q      = state_q[2];  // the next byte is a data byte
    wire          pend_q      = state_q[1];  // a packet ended by its length byte waits to be handed over
    wire          stop_q      = state_q[0];  // the next byte waits while hold_i (below)
    reg           own_q;
    reg           probe_q;
    reg  [2:0]    rem_q;    // data bytes after the next one
    reg           last_q;   // the next data byte is the packet's last
    reg  [7:0]    pos_q;    // one-hot: the slot of the next data byte
    reg  [LW-1:0] idle_q;   // x^(idle ticks) mod the polynomial (above)
    // The packet handed to the executor.
    reg           pkt_valid_q;
    reg  [1:0]    pkt_kind_q;
    reg  [3:0]    pkt_n_q;
    reg  [7:0]    pkt_d0_q, pkt_d1_q, pkt_d2_q;
    reg  [7:0]    pkt_cmd_q;
    reg  [NUM_PINS-1:0] pkt_sel_q;
    reg  [39:0]   pkt_tail_q;

    assign pkt_valid_o = pkt_valid_q;
    assign pkt_kind_o  = pkt_kind_q;
    assign pkt_n_o     = pkt_n_q;
    assign pkt_d0_o    = pkt_d0_q;
    assign pkt_cmd_o   = pkt_cmd_q;
    assign pkt_d1_o    = pkt_d1_q;
    assign pkt_sel_o   = pkt_sel_q;
    assign pkt_d2_o    = pkt_d2_q;
    assign pkt_tail_o  = pkt_tail_q;

    // Flow control. A packet that can need the reply slot is handed over only
    // while the slot is free and no packet is being executed (hold_i 0), so
    // execution itself never waits:
    // - a packet for this module: its last data byte waits, so a command
    //   always executes a fixed 2 clocks after its last byte;
    // - a packet that ends with its length byte and has a reply (0xAD with
    //   N = 0, this module with N > 8): the length byte is taken and the
    //   packet waits in pend_q, where the next byte waits with it.
    // s_axis_tready thus comes from flops and hold_i only, never from the
    // offered byte. Every other byte streams at one per clock.
    assign s_axis_tready = !rst && !(hold_i && stop_q);

    // The next state is written as "stop_q ? .. : ..": hold_i matters only
    // while stop_q is 1 (stop_q = pend_q || data_q && own_q && last_q), so the
    // late hold_i selects between terms that do not wait for it. rst resets
    // every register the terms below steer.
    //
    // Everything that reads the offered byte is a function called in the
    // clocked block, not a wire: a simulator then works the input's logic out
    // once a clock, at the edge, where wires would have it worked out as the
    // inputs change and again after each edge. (The functions read the
    // flops and hold_i, tick_i directly; synthesis gives the same gates.)

    // The byte is taken: it is offered and nothing holds it.
    function take(input v);
        take = v && !(hold_i && stop_q);
    endfunction
    // Byte decode from plain gates, not adders or magnitude comparators.
    function len_zero(input [7:0] b);
        len_zero = ~|b;
    endfunction
    function len_over(input [7:0] b);  // > 8
        len_over = (|b[7:4]) | (b[3] & (|b[2:0]));
    endfunction
    // pkt_cmd_o's flags of a d0 byte (bit numbers CMDF_*, bsd_protocol.vh).
    function [7:0] cmd_flags(input [7:0] b);
        begin
            cmd_flags                = 8'd0;
            cmd_flags[CMDF_HB]       = b == CMD_HB;
            cmd_flags[CMDF_DEBUG]    = b == CMD_DEBUG;
            cmd_flags[CMDF_RESET]    = b == CMD_RESET;
            cmd_flags[CMDF_DIG_CFG]  = b == CMD_DIG_CFG;
            cmd_flags[CMDF_DIG_IO]   = b == CMD_DIG_IO;
            cmd_flags[CMDF_DIG_RST]  = b == CMD_DIG_RST;
            cmd_flags[CMDF_PTIME_RD] = b == CMD_PTIME_RD;
            cmd_flags[CMDF_ANY]      = |cmd_flags;
        end
    endfunction
    // N is 1..8 where it is read, so N = 1 shows in its low 3 bits alone.
    function len_one(input [2:0] b);
        len_one = b == 3'd1;
    endfunction

    // {len, data, pend, stop, pkt_valid}: the state flags' next values. The two cases in which
    // every flag but pkt_valid keeps its value (a byte held: hold_i in stop_q; no byte and no
    // tick outside stop_q) have branches of their own with the values of the general terms,
    // so that a simulator works out a test or two on those clocks, not the terms.
    function [4:0] next_state(input v, input [7:0] b);
        reg tmo, to_pend, to_data;
        begin
            if (stop_q && hold_i) begin
                next_state = {1'b0, data_q, pend_q, 2'b10};
            end else if (stop_q) begin
                tmo = (RX_TIMEOUT_US != 0) && tick_i && idle_q == IDLE_END;
                next_state = {pend_q && v, data_q && !v && !tmo, 1'b0,
                              data_q && !v && !tmo, pend_q || (data_q && v)};
            end else if (!v && !tick_i) begin
                next_state = {len_q, data_q, 3'b000};
            end else if (data_q) begin
                // (stop_q is 0 here, so pend_q is too: data_q, len_q or neither, each with
                // a branch of its own, so that a simulator decodes the byte as N only for N)
                tmo        = (RX_TIMEOUT_US != 0) && tick_i && idle_q == IDLE_END;
                next_state = {1'b0, v ? !last_q : !tmo, 1'b0, v && own_q && rem_q == 3'd1, 1'b0};
            end else if (len_q) begin
                tmo     = (RX_TIMEOUT_US != 0) && tick_i && idle_q == IDLE_END;
                to_pend = (own_q && len_over(b)) || (probe_q && len_zero(b));
                to_data = !len_over(b) && !len_zero(b);
                // (a packet to this module with its next byte its last, or a packet pending)
                next_state = {!v && !tmo, v && to_data, v && to_pend,
                              v && ((to_data && own_q && len_one(b[2:0])) || to_pend), 1'b0};
            end else begin
                next_state = {v, 4'b0000};
            end
        end
    endfunction

    // (Ordered so that each flop is read before it is written, as far as
    // the loops between them allow: a simulator then keeps fewer copies. The
    // next state first: it reads every flop but the slots, and only the state
    // flags it writes are read after it.)
    always @(posedge clk) begin
        {state_q, pkt_valid_q} <= next_state(s_axis_tvalid, s_axis_tdata);
        // N and the data bytes take the offered byte whether or not it is
        // accepted (no tvalid or tready in these enables): the slot of the next
        // data byte follows the offered byte until it is taken, so it ends
        // with the byte taken, and the executor reads them only on
        // pkt_valid_q's clock, after the last one. A slot past N may take
        // later bytes; the executor uses only the first N. No reset: from
        // reset to the first N every slot takes the offered byte.
        if (len_q) pkt_n_q <= s_axis_tdata[3:0];
        if (pos_q[0]) begin
            pkt_d0_q  <= s_axis_tdata;
            pkt_cmd_q <= cmd_flags(s_axis_tdata);
        end
        if (pos_q[1]) begin
            pkt_d1_q  <= s_axis_tdata;
            pkt_sel_q <= SEL_ONE << s_axis_tdata[5:0];
        end
        if (pos_q[2]) pkt_d2_q <= s_axis_tdata;
        // (d3..d7 come only with cmdDEBUG: one test for the five on other clocks)
        if (|pos_q[7:3]) begin
            if (pos_q[3]) pkt_tail_q[39:32] <= s_axis_tdata;
            if (pos_q[4]) pkt_tail_q[31:24] <= s_axis_tdata;
            if (pos_q[5]) pkt_tail_q[23:16] <= s_axis_tdata;
            if (pos_q[6]) pkt_tail_q[15:8]  <= s_axis_tdata;
            if (pos_q[7]) pkt_tail_q[7:0]   <= s_axis_tdata;
        end

        if (data_q && take(s_axis_tvalid)) begin  // a data byte
            last_q <= rem_q == 3'd1;
            rem_q  <= rem_q - 3'd1;
            pos_q  <= {pos_q[6:0], 1'b0};
        end
        if (len_q && s_axis_tvalid) begin  // N (stop_q is 0 in len_q)
            rem_q  <= s_axis_tdata[2:0] - 3'd1;
            last_q <= len_one(s_axis_tdata[2:0]);
            pos_q  <= 8'd1;
            // The kind of the packet this N makes (a command if it has data).
            pkt_kind_q <= (own_q && len_over(s_axis_tdata)) ? KIND_SERIAL :
                          (probe_q && len_zero(s_axis_tdata)) ? KIND_PROBE : KIND_CMD;
        end
        if (!len_q && !data_q && take(s_axis_tvalid)) begin  // an address
            own_q   <= s_axis_tdata == ADDR_OWN;
            probe_q <= s_axis_tdata == ADDR_RESYNC;
        end
        // Idle ticks count while a partial packet could take a byte and none
        // is offered; the TIMEOUT_TICKS-th drops the packet.
        // (The step first, then the restart, which excludes it: idle_q is read before
        // it is written.)
        // (nested under the tick, the rarest term: a simulator tests one bit on most clocks)
        if (tick_i) begin
            if (!s_axis_tvalid && !(hold_i && stop_q) && (len_q || data_q))
                idle_q <= {idle_q[LW-2:0], 1'b0} ^ ({LW{idle_q[LW-1]}} & LFSR_P[LW-1:0]);
        end
        if (take(s_axis_tvalid)) idle_q <= {{(LW-1){1'b0}}, 1'b1};
        if (rst) begin
            state_q     <= 4'd0;
            pkt_valid_q <= 1'b0;
            own_q       <= 1'b0;
            probe_q     <= 1'b0;
            pos_q       <= 8'hFF;  // every slot follows the stream until the first N
            idle_q      <= {{(LW-1){1'b0}}, 1'b1};
            pkt_kind_q  <= KIND_CMD;
        end
    end

`ifdef FORMAL
`include "bsd_parser_props.vh"
`endif
endmodule
`default_nettype wire
