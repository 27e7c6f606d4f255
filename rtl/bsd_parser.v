`default_nettype none
// Byte framing of host packets: address, N, d0 .. d(N-1).
// Hands each complete packet that needs action to the executor as a
// one-clock pulse with its first three data bytes and N. Packets for other
// addresses are consumed silently; N > 8 resyncs on the next byte; a partial
// packet is dropped after RX_TIMEOUT_US of waiting for a byte.
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
    output reg        pkt_valid_o,
    output reg  [1:0] pkt_kind_o,
    output reg  [3:0] pkt_n_o,
    output reg  [7:0] pkt_d0_o,
    output reg  [7:0] pkt_d1_o,
    output reg  [7:0] pkt_d2_o
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

    reg  [1:0]    state_q;
    reg           own_q;
    reg           probe_q;
    reg  [3:0]    cnt_q;
    reg           last_q;   // the next data byte is the packet's last
    reg  [TW-1:0] idle_q;

    // Decoded from registers and plain gates, not adders or magnitude
    // comparators: these feed s_axis_tready and the accept strobe.
    wire last_data = last_q;
    wire len_zero  = ~|s_axis_tdata;
    wire len_over  = (|s_axis_tdata[7:4]) | (s_axis_tdata[3] & (|s_axis_tdata[2:0]));  // > 8

    // The last byte of a packet that can need the reply slot waits while the
    // slot is (or is about to be) full, so execution itself never waits. That
    // is the last data byte of a packet for this module, or a length byte that
    // ends a packet with a reply: 0xAD with N = 0, this module with N > 8.
    // The latter makes s_axis_tready depend on the offered byte, which
    // AXI-Stream allows (with tvalid 0 it is 1 there, so an idle input counts
    // towards the timeout). Every other byte streams at one per clock.
    wire may_reply = (state_q == ST_LEN && s_axis_tvalid &&
                      ((probe_q && len_zero) || (own_q && len_over))) ||
                     (state_q == ST_DATA && own_q && last_data);

    assign s_axis_tready = !rst && !(hold_i && may_reply);

    wire accept  = s_axis_tvalid && s_axis_tready;
    wire waiting = s_axis_tready && !s_axis_tvalid && state_q != ST_ADDR;
    wire expired = (RX_TIMEOUT_US != 0) && waiting && tick_i &&
                   (idle_q == TIMEOUT_TICKS[TW-1:0] - 1'b1);

    always @(posedge clk) begin
        pkt_valid_o <= 1'b0;
        if (accept) idle_q <= {TW{1'b0}};
        else if (waiting && tick_i) idle_q <= idle_q + 1'b1;

        if (expired) begin
            state_q <= ST_ADDR;
        end else if (accept) begin
            case (state_q)
                ST_ADDR: begin
                    own_q   <= (s_axis_tdata == ADDR_OWN);
                    probe_q <= (s_axis_tdata == ADDR_RESYNC);
                    state_q <= ST_LEN;
                end
                ST_LEN: begin
                    pkt_n_o <= s_axis_tdata[3:0];
                    cnt_q   <= 4'd0;
                    last_q  <= s_axis_tdata == 8'd1;
                    if (len_over) begin
                        pkt_valid_o <= own_q;
                        pkt_kind_o  <= KIND_SERIAL;
                        state_q     <= ST_ADDR;
                    end else if (len_zero) begin
                        pkt_valid_o <= probe_q;
                        pkt_kind_o  <= KIND_PROBE;
                        state_q     <= ST_ADDR;
                    end else begin
                        state_q <= ST_DATA;
                    end
                end
                default: begin
                    case (cnt_q)
                        4'd0:    pkt_d0_o <= s_axis_tdata;
                        4'd1:    pkt_d1_o <= s_axis_tdata;
                        4'd2:    pkt_d2_o <= s_axis_tdata;
                        default: ;
                    endcase
                    cnt_q  <= cnt_q + 4'd1;
                    last_q <= cnt_q + 4'd2 == pkt_n_o;
                    if (last_data) begin
                        pkt_valid_o <= own_q;
                        pkt_kind_o  <= KIND_CMD;
                        state_q     <= ST_ADDR;
                    end
                end
            endcase
        end

        if (rst) begin
            state_q     <= ST_ADDR;
            own_q       <= 1'b0;
            probe_q     <= 1'b0;
            cnt_q       <= 4'd0;
            last_q      <= 1'b0;
            idle_q      <= {TW{1'b0}};
            pkt_valid_o <= 1'b0;
            pkt_kind_o  <= KIND_CMD;
            pkt_n_o     <= 4'd0;
            pkt_d0_o    <= 8'd0;
            pkt_d1_o    <= 8'd0;
            pkt_d2_o    <= 8'd0;
        end
    end
endmodule
`default_nettype wire
