// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Sends whole packets `A, N, d0..` onto m_axis, the oldest waiting source
// first. Source s offers N (0..4) and up to four data bytes; source LONG_SRC
// (the command reply, for cmdDEBUG's echo) may offer N up to 8 and four more
// bytes on long_n3_i/long_data_i (N's bit 3, data bytes 4..7; none when
// LONG_SRC < 0). Each source keeps its
// request up, and its packet unchanged, until done_o[s] pulses with the
// handshake of its last byte, so a source is "delivered" only when its
// packet has left the core.
//
// Two registers: the packet going out (a shift register) and the source of
// the next one, staged from the arbiter while the current one is sent. The
// output loads the staged source's packet on the clock of its own last
// handshake, so packets leave back to back, and m_axis_tready only gates
// register enables (the arbiter and the source mux never wait for it; the
// mux is driven by the staged source, a register, not by the grant). Later
// events are always younger, so staging early never reorders packets.
//
// flush_i (cmdRESET) drops every packet not yet started while the sources are
// reset around it. A packet with a byte already taken is finished, so the
// host's framing holds, and credits nobody. One whose first byte is offered
// but not yet taken cannot be withdrawn (AXI-Stream), but every packet starts
// with the address, so it becomes the power-up message in place and is
// credited to POWERUP_SRC, the source that holds that message after a reset.
module bsd_tx #(
    parameter integer MODULE_ADDR = 2,
    parameter integer K           = 2,
    parameter integer LONG_SRC    = -1,
    parameter integer POWERUP_SRC = -1
) (
    input  wire            clk,
    input  wire            rst,
    input  wire            flush_i,
    input  wire [K-1:0]    req_i,
    input  wire [3*K-1:0]  n_i,
    input  wire [32*K-1:0] data_i,   // source s: data_i[32*s+24 +: 8] is d0
    input  wire            long_n3_i,    // source LONG_SRC: bit 3 of its N
    input  wire [31:0]     long_data_i,  // and its d4..d7, d4 in the top byte
    output wire [K-1:0]    done_o,
    output wire [7:0]      m_axis_tdata,
    output wire            m_axis_tvalid,
    input  wire            m_axis_tready,
    output wire            m_axis_tlast
);
    `include "bsd_protocol.vh"

    localparam [7:0] ADDR_OWN = MODULE_ADDR[7:0];

    // The packet going out.
    reg  [79:0]  buf_q;    // bytes still to send, first in the top byte
    reg  [3:0]   left_q;   // bytes still to send
    reg          last_q;   // left_q == 1: the byte offered is the packet's last
    reg          valid_q;
    reg  [K-1:0] cur_q;    // its source (0 when none: cur_q, next_src_q and
                           // done_q are the sources the arbiter must skip)
    reg          first_q;  // no byte of it taken yet
    // The next packet's source.
    reg          next_valid_q;
    reg  [K-1:0] next_src_q;

    reg  [K-1:0] done_q;   // sources whose request falls this clock

    wire [K-1:0] gnt;
    wire hs    = valid_q && m_axis_tready;
    wire load  = next_valid_q && !flush_i && (!valid_q || (hs && last_q));
    // The packet offered at a flush has no byte taken: it becomes the power-up message.
    wire swap  = flush_i && valid_q && first_q && !m_axis_tready;
    // The staging register samples the arbiter whenever it is free: its
    // enable never waits for the grant.
    wire stage = !next_valid_q || load;

    bsd_age_arb #(.K(K)) u_arb (
        .clk       (clk),
        .rst       (rst || flush_i),
        .req_i     (req_i),
        .exclude_i (cur_q | next_src_q | done_q),
        .gnt_o     (gnt)
    );

    // The staged source's packet (it stays unchanged until it has left).
    reg [3:0]  sel_n;
    reg [31:0] sel_data;
    reg [31:0] sel_long;
    integer s;
    always @* begin
        sel_n    = 4'd0;
        sel_data = 32'd0;
        sel_long = 32'd0;
        for (s = 0; s < K; s = s + 1) begin
            if (next_src_q[s]) begin
                sel_n    = sel_n | {1'b0, n_i[3*s +: 3]};
                sel_data = sel_data | data_i[32*s +: 32];
                if (s == LONG_SRC) begin
                    sel_n[3] = long_n3_i;
                    sel_long = long_data_i;
                end
            end
        end
    end

    // The sources whose packet's last byte leaves now.
    wire [K-1:0] done = (hs && last_q) ? cur_q : {K{1'b0}};
    assign done_o = done;

    // The one-hot of POWERUP_SRC (none when it is out of range).
    localparam [K:0] POWERUP_BIT = (POWERUP_SRC >= 0 && POWERUP_SRC < K) ? ({{K{1'b0}}, 1'b1} << POWERUP_SRC) : {(K+1){1'b0}};

    always @(posedge clk) begin
        if (load) begin
            buf_q   <= {ADDR_OWN, 4'd0, sel_n, sel_data, sel_long};
            left_q  <= sel_n + 4'd2;
            last_q  <= 1'b0;  // a packet is at least A, N
            valid_q <= 1'b1;
            cur_q   <= next_src_q;
            first_q <= 1'b1;
        end else if (hs) begin
            buf_q   <= {buf_q[71:0], 8'd0};
            left_q  <= left_q - 4'd1;
            last_q  <= left_q == 4'd2;
            first_q <= 1'b0;
            if (last_q) begin
                valid_q <= 1'b0;
                cur_q   <= {K{1'b0}};
            end
        end
        if (stage) begin
            next_src_q   <= gnt;
            next_valid_q <= |gnt;
        end
        done_q <= done;
        if (flush_i) begin
            next_src_q   <= {K{1'b0}};
            next_valid_q <= 1'b0;
            done_q       <= {K{1'b0}};
            if (!swap) cur_q <= {K{1'b0}};
        end
        if (swap) begin
            buf_q  <= {ADDR_OWN, MSG_N, CMD_MSG, MSG_STATE_POWER_RESET, 48'd0};
            left_q <= 4'd4;
            last_q <= 1'b0;
            cur_q  <= POWERUP_BIT[K-1:0];
        end
        if (rst) begin
            buf_q        <= 80'd0;
            left_q       <= 4'd0;
            last_q       <= 1'b0;
            valid_q      <= 1'b0;
            cur_q        <= {K{1'b0}};
            first_q      <= 1'b0;
            next_valid_q <= 1'b0;
            next_src_q   <= {K{1'b0}};
            done_q       <= {K{1'b0}};
        end
    end

    assign m_axis_tdata  = buf_q[79:72];
    assign m_axis_tvalid = valid_q;
    assign m_axis_tlast  = last_q;

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the formal props assert it
    // A source keeps its request up, and its packet (N and its first N data bytes)
    // unchanged, from its request until done_o pulses for it.
    reg  [K-1:0]    chk_req_q;
    reg  [K-1:0]    chk_done_q;
    reg  [3*K-1:0]  chk_n_q;
    reg  [32*K-1:0] chk_data_q;
    // The bytes of a packet of N data bytes within data_i's 32 bits (d0 on top).
    function [31:0] chk_mask(input [2:0] n);
        chk_mask = ~(32'hFFFFFFFF >> (8 * n));
    endfunction
    integer c;
    always @(posedge clk) begin
        for (c = 0; c < K; c = c + 1) begin
            if (!rst && chk_req_q[c] && !chk_done_q[c]) begin
                if (!req_i[c])
                    $fatal(1, "bsd_tx: source %0d dropped its request before done_o", c);
                if (n_i[3*c +: 3] != chk_n_q[3*c +: 3]
                        || ((data_i[32*c +: 32] ^ chk_data_q[32*c +: 32]) & chk_mask(n_i[3*c +: 3])) != 32'd0)
                    $fatal(1, "bsd_tx: source %0d changed its packet before done_o", c);
            end
        end
        chk_req_q  <= (rst || flush_i) ? {K{1'b0}} : req_i;  // the sources are reset with a flush
        chk_done_q <= done;
        chk_n_q    <= n_i;
        chk_data_q <= data_i;
    end
`endif
`endif

`ifdef FORMAL
`include "bsd_tx_props.vh"
`endif
endmodule
`default_nettype wire
