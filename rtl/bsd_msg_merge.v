// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Merges one fixed message packet `A, 2, 0x80, CODE` into a packet stream,
// only between packets: while a packet of the stream is part-way out (a byte
// has left, its tlast not yet), the message waits; while the message is
// going out, the stream is held (s_axis_tready 0). Once the message's first
// byte is offered it goes out whole. At a packet boundary a waiting message
// goes first, unless a stream byte is already offered and stalled
// (AXI-Stream: an offered byte stays offered until taken). req_i is a level;
// done_o pulses with the handshake of the message's last byte.
module bsd_msg_merge #(
    parameter integer MODULE_ADDR = 2,
    parameter [7:0]   CODE        = 8'd0  // the message code, set by the instance (no default message)
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       req_i,
    output wire       done_o,
    input  wire [7:0] s_axis_tdata,
    input  wire       s_axis_tvalid,
    output wire       s_axis_tready,
    input  wire       s_axis_tlast,
    output wire [7:0] m_axis_tdata,
    output wire       m_axis_tvalid,
    input  wire       m_axis_tready,
    output wire       m_axis_tlast
);
    `include "bsd_protocol.vh"

    localparam [7:0] ADDR_OWN = MODULE_ADDR[7:0];
    localparam [7:0] MSG_CODE = CODE[7:0];

    reg       mid_q;    // a stream packet is part-way out
    reg       stall_q;  // a stream byte was offered and not taken: it stays offered
    reg       msg_q;    // the message is part-way out (or offered)
    reg [1:0] idx_q;    // message byte being offered

    wire start    = req_i && !mid_q && !stall_q && !msg_q;
    wire msg      = msg_q || start;         // the message is offered now
    wire msg_last = (idx_q == 2'd3);        // its byte offered is its last

    reg [7:0] msg_byte;
    always @* begin
        case (idx_q)
            2'd0:    msg_byte = ADDR_OWN;
            2'd1:    msg_byte = MSG_N;
            2'd2:    msg_byte = CMD_MSG;
            default: msg_byte = MSG_CODE;
        endcase
    end

    assign m_axis_tdata  = msg ? msg_byte : s_axis_tdata;
    assign m_axis_tvalid = msg || s_axis_tvalid;
    assign m_axis_tlast  = msg ? msg_last : s_axis_tlast;
    assign s_axis_tready = !msg && m_axis_tready;
    assign done_o        = msg && m_axis_tready && msg_last;

    always @(posedge clk) begin
        stall_q <= !msg && s_axis_tvalid && !m_axis_tready;
        if (msg) begin
            msg_q <= !(m_axis_tready && msg_last);
            if (m_axis_tready) idx_q <= idx_q + 1'b1;
        end else if (s_axis_tvalid && m_axis_tready) begin
            mid_q <= !s_axis_tlast;
        end
        if (rst) begin
            mid_q   <= 1'b0;
            stall_q <= 1'b0;
            msg_q   <= 1'b0;
            idx_q   <= 2'd0;
        end
    end

`ifdef FORMAL
`include "bsd_msg_merge_props.vh"
`endif
endmodule
`default_nettype wire
