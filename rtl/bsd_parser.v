// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Byte framing of host packets: address, N, d0 .. d(N-1). Hands each
// complete packet that needs action to the executor as a one-clock pulse with
// N and its data bytes (d0..d2 for the commands, d3..d7 for cmdDEBUG's echo).
// Packets for other addresses are consumed silently; N > 8 resyncs on the
// next byte; a partial packet is dropped after RX_TIMEOUT_US of waiting for a
// byte.
module bsd_parser #(
    parameter integer MODULE_ADDR   = 2,
    parameter integer RX_TIMEOUT_US = 25_600
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
    output wire [7:0] pkt_d1_o,
    output wire [7:0] pkt_d2_o,
    output wire [39:0] pkt_tail_o    // d3..d7, d3 in the top byte (cmdDEBUG echoes them)
);
    `include "bsd_protocol.vh"

    localparam [7:0] ADDR_OWN = MODULE_ADDR[7:0];

    // Idle ticks that drop a partial packet: one more than ceil(US / 1.6),
    // so the drop never comes before RX_TIMEOUT_US whatever the tick phase.
    localparam integer TIMEOUT_TICKS = (RX_TIMEOUT_US * 5 + 7) / 8 + 1;
    localparam integer TW = $clog2(TIMEOUT_TICKS + 1);

    localparam [1:0] ST_ADDR = 2'd0;
    localparam [1:0] ST_LEN  = 2'd1;
    localparam [1:0] ST_DATA = 2'd2;
    localparam [1:0] ST_PEND = 2'd3;  // a packet ended by its length byte waits to be handed over

    // ------------------------------------------------------------ registers
    reg  [1:0]    state_q;
    reg           own_q;
    reg           probe_q;
    reg  [3:0]    cnt_q;
    reg           last_q;   // the next data byte is the packet's last
    reg           stop_q;   // the next byte waits while hold_i (below)
    reg  [TW-1:0] idle_q;
    // The packet handed to the executor.
    reg           pkt_valid_q;
    reg  [1:0]    pkt_kind_q;
    reg  [3:0]    pkt_n_q;
    reg  [7:0]    pkt_d0_q, pkt_d1_q, pkt_d2_q;
    reg  [39:0]   pkt_tail_q;

    assign pkt_valid_o = pkt_valid_q;
    assign pkt_kind_o  = pkt_kind_q;
    assign pkt_n_o     = pkt_n_q;
    assign pkt_d0_o    = pkt_d0_q;
    assign pkt_d1_o    = pkt_d1_q;
    assign pkt_d2_o    = pkt_d2_q;
    assign pkt_tail_o  = pkt_tail_q;

    // Flow control. A packet that can need the reply slot is handed over only
    // while the slot is free and no packet is being executed (hold_i 0), so
    // execution itself never waits:
    // - a packet for this module: its last data byte waits, so a command
    //   always executes a fixed 2 clocks after its last byte;
    // - a packet that ends with its length byte and has a reply (0xAD with
    //   N = 0, this module with N > 8): the length byte is taken and the
    //   packet waits in ST_PEND, where the next byte waits with it.
    // s_axis_tready thus comes from flops and hold_i only, never from the
    // offered byte. Every other byte streams at one per clock.
    assign s_axis_tready = !rst && !(hold_i && stop_q);

    wire accept  = s_axis_tvalid && s_axis_tready;
    wire hand_over = state_q == ST_PEND && !hold_i;
    wire waiting = s_axis_tready && !s_axis_tvalid && (state_q == ST_LEN || state_q == ST_DATA);
    wire expired = (RX_TIMEOUT_US != 0) && waiting && tick_i &&
                   (idle_q == TIMEOUT_TICKS[TW-1:0] - 1'b1);

    // Byte decode from plain gates, not adders or magnitude comparators.
    wire len_zero = ~|s_axis_tdata;
    wire len_over = (|s_axis_tdata[7:4]) | (s_axis_tdata[3] & (|s_axis_tdata[2:0]));  // > 8

    // ---------------------------------------------------- next-state logic
    reg  [1:0] state_d;
    reg        own_d, probe_d, last_d;
    reg  [3:0] cnt_d;
    reg        pkt_valid_d;
    reg  [1:0] pkt_kind_d;

    always @* begin
        state_d     = state_q;
        own_d       = own_q;
        probe_d     = probe_q;
        cnt_d       = cnt_q;
        last_d      = last_q;
        pkt_valid_d = hand_over;
        pkt_kind_d  = pkt_kind_q;
        if (hand_over) state_d = ST_ADDR;
        if (expired) begin
            state_d = ST_ADDR;
        end else if (accept) begin
            case (state_q)
                ST_ADDR, ST_PEND: begin
                    own_d   = s_axis_tdata == ADDR_OWN;
                    probe_d = s_axis_tdata == ADDR_RESYNC;
                    state_d = ST_LEN;
                end
                ST_LEN: begin
                    cnt_d  = 4'd0;
                    last_d = s_axis_tdata == 8'd1;
                    if (own_q && len_over) begin
                        pkt_kind_d = KIND_SERIAL;
                        state_d    = ST_PEND;
                    end else if (probe_q && len_zero) begin
                        pkt_kind_d = KIND_PROBE;
                        state_d    = ST_PEND;
                    end else if (len_over || len_zero) begin
                        state_d = ST_ADDR;
                    end else begin
                        state_d = ST_DATA;
                    end
                end
                default: begin
                    cnt_d  = cnt_q + 4'd1;
                    last_d = cnt_q + 4'd2 == pkt_n_q;
                    if (last_q) begin
                        pkt_valid_d = own_q;
                        pkt_kind_d  = KIND_CMD;
                        state_d     = ST_ADDR;
                    end
                end
            endcase
        end
    end

    always @(posedge clk) begin
        state_q     <= state_d;
        own_q       <= own_d;
        probe_q     <= probe_d;
        cnt_q       <= cnt_d;
        last_q      <= last_d;
        stop_q      <= (state_d == ST_DATA && own_d && last_d) || state_d == ST_PEND;
        pkt_valid_q <= pkt_valid_d;
        pkt_kind_q  <= pkt_kind_d;
        if (accept) idle_q <= {TW{1'b0}};
        else if (waiting && tick_i) idle_q <= idle_q + 1'b1;

        // The packet's N and first data bytes take the offered byte whether or
        // not it is accepted, so s_axis_tready stays off these enables: a held
        // byte stays offered unchanged (AXI-Stream), and the executor reads
        // them only on pkt_valid_q's clock, when the parser waits for an
        // address byte and so writes none of them.
        if (s_axis_tvalid && state_q == ST_LEN) pkt_n_q <= s_axis_tdata[3:0];
        if (s_axis_tvalid && state_q == ST_DATA) begin
            case (cnt_q)
                4'd0:    pkt_d0_q <= s_axis_tdata;
                4'd1:    pkt_d1_q <= s_axis_tdata;
                4'd2:    pkt_d2_q <= s_axis_tdata;
                4'd3:    pkt_tail_q[39:32] <= s_axis_tdata;
                4'd4:    pkt_tail_q[31:24] <= s_axis_tdata;
                4'd5:    pkt_tail_q[23:16] <= s_axis_tdata;
                4'd6:    pkt_tail_q[15:8]  <= s_axis_tdata;
                4'd7:    pkt_tail_q[7:0]   <= s_axis_tdata;
                // cnt_q is 0..7 in ST_DATA (N > 8 never gets there): never runs.
                /* verilator coverage_off */
                default: ;
                /* verilator coverage_on */
            endcase
        end

        if (rst) begin
            state_q     <= ST_ADDR;
            own_q       <= 1'b0;
            probe_q     <= 1'b0;
            cnt_q       <= 4'd0;
            last_q      <= 1'b0;
            stop_q      <= 1'b0;
            idle_q      <= {TW{1'b0}};
            pkt_valid_q <= 1'b0;
            pkt_kind_q  <= KIND_CMD;
            pkt_n_q     <= 4'd0;
            pkt_d0_q    <= 8'd0;
            pkt_d1_q    <= 8'd0;
            pkt_d2_q    <= 8'd0;
            pkt_tail_q  <= 40'd0;
        end
    end

`ifdef FORMAL
`include "bsd_parser_props.vh"
`endif
endmodule
`default_nettype wire
