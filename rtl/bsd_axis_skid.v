// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// AXI-Stream register slice (skid buffer): every output comes from a flop,
// s_axis_tready included, so no combinational path crosses it in either
// direction, and it still moves one word per clock. A word accepted while
// the output is stalled waits in the skid register; tready drops only then.
// Latency: 1 clock.
module bsd_axis_skid #(
    parameter integer WIDTH = 8
) (
    input  wire             clk,
    input  wire             rst,
    input  wire [WIDTH-1:0] s_axis_tdata,
    input  wire             s_axis_tvalid,
    output wire             s_axis_tready,
    output wire [WIDTH-1:0] m_axis_tdata,
    output wire             m_axis_tvalid,
    input  wire             m_axis_tready
);
    reg [WIDTH-1:0] skid_q;
    reg             skid_valid_q;
    // The output register.
    reg [WIDTH-1:0] out_data_q;
    reg             out_valid_q;

    assign s_axis_tready = !skid_valid_q;
    assign m_axis_tdata  = out_data_q;
    assign m_axis_tvalid = out_valid_q;

    wire advance = m_axis_tready || !out_valid_q;

    // The two valid flags' next values are written as one expression each,
    // not as enables: m_axis_tready (a consumer's handshake logic) then
    // reaches a flop's data input through a gate or two, never its enable
    // or reset pin.
    always @(posedge clk) begin
        if (advance) out_data_q <= skid_valid_q ? skid_q : s_axis_tdata;
        if (!advance && !skid_valid_q) skid_q <= s_axis_tdata;
        // The output holds a word unless it advances with none to take.
        out_valid_q  <= !rst && (!advance || skid_valid_q || s_axis_tvalid);
        // The skid fills only while the output waits, and empties when it advances.
        skid_valid_q <= !rst && !advance && (skid_valid_q || s_axis_tvalid);
    end

`ifdef FORMAL
`include "bsd_axis_skid_props.vh"
`endif
endmodule
`default_nettype wire
