// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Measurement harness for brainstem_dio alone: the bare core has more port
// bits than a UP5K-SG48 has pins, so every core input comes from a flop of a
// shift register fed by one pin, and every core output goes into a flop and
// then an XOR tree (itself registered) to one pin. The core's ports are thus
// flop-to-port and port-to-flop, as in a real design, and no logic is
// optimized away. The harness costs about 1 LUT + 2 FFs per core port bit;
// docs/synthesis.md reports the core's own cells from a separate yosys run.
module core_wrap #(
    parameter integer          NUM_PINS      = 5,
    parameter [NUM_PINS-1:0]   TIMER_MASK    = 5'b11110,
    parameter integer          PIN_ID_BASE   = 5,
    parameter integer          TIMER_ID_BASE = 10,
    parameter integer          TRANS_ID_BASE = 15,
    parameter integer          CLK_HZ        = 12_000_000
) (
    input  wire clk,
    input  wire din,
    output reg  dout
);
    localparam integer NI = 8 + 1 + 1 + 1 + NUM_PINS;                // rst, s_axis, m_axis_tready, pin_i
    localparam integer NO = 1 + 8 + 1 + 1 + 3 * NUM_PINS + 1 + 6 + 16 + 1;

    reg  [NI-1:0] in_q;
    reg  [NO-1:0] out_q;
    wire [NO-1:0] out_w;

    always @(posedge clk) begin
        in_q  <= {in_q[NI-2:0], din};
        out_q <= out_w;
        dout  <= ^out_q;
    end

    brainstem_dio #(
        .CLK_HZ        (CLK_HZ),
        .NUM_PINS      (NUM_PINS),
        .TIMER_MASK    (TIMER_MASK),
        .PIN_ID_BASE   (PIN_ID_BASE),
        .TIMER_ID_BASE (TIMER_ID_BASE),
        .TRANS_ID_BASE (TRANS_ID_BASE)
    ) u_core (
        .clk           (clk),
        .rst           (in_q[0]),
        .s_axis_tdata  (in_q[8:1]),
        .s_axis_tvalid (in_q[9]),
        .s_axis_tready (out_w[0]),
        .m_axis_tdata  (out_w[8:1]),
        .m_axis_tvalid (out_w[9]),
        .m_axis_tready (in_q[10]),
        .m_axis_tlast  (out_w[10]),
        .pin_i         (in_q[11 +: NUM_PINS]),
        .pin_o         (out_w[11 +: NUM_PINS]),
        .pin_oe        (out_w[11 + NUM_PINS +: NUM_PINS]),
        .raw_trans     (out_w[11 + 2 * NUM_PINS +: NUM_PINS]),
        .rflx_valid    (out_w[11 + 3 * NUM_PINS]),
        .rflx_id       (out_w[12 + 3 * NUM_PINS +: 6]),
        .rflx_data     (out_w[18 + 3 * NUM_PINS +: 16]),
        .link_up       (out_w[34 + 3 * NUM_PINS])
    );
endmodule
`default_nettype wire
