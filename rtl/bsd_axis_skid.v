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
    output reg  [WIDTH-1:0] m_axis_tdata,
    output reg              m_axis_tvalid,
    input  wire             m_axis_tready
);
    reg [WIDTH-1:0] skid_q;
    reg             skid_valid_q;

    assign s_axis_tready = !skid_valid_q;

    wire advance = m_axis_tready || !m_axis_tvalid;

    always @(posedge clk) begin
        if (advance) begin
            if (skid_valid_q) begin
                m_axis_tdata  <= skid_q;
                m_axis_tvalid <= 1'b1;
                skid_valid_q  <= 1'b0;
            end else begin
                m_axis_tdata  <= s_axis_tdata;
                m_axis_tvalid <= s_axis_tvalid;
            end
        end else if (s_axis_tvalid && !skid_valid_q) begin
            skid_q       <= s_axis_tdata;
            skid_valid_q <= 1'b1;
        end
        if (rst) begin
            m_axis_tvalid <= 1'b0;
            skid_valid_q  <= 1'b0;
        end
    end
endmodule
`default_nettype wire
