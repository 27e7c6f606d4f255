// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Measurement harness for brainstem_dio_uart with more pins than an iCE40UP5K
// package bonds (SG48: 39 IOs): the pads are serialized, as a board would do
// with shift-register chips (74HC165 in, 74HC595 out). pin_i comes from a shift
// register fed by one pin; pin_o and pin_oe are loaded in parallel into a
// shift register read out on one pin. The outputs no pad needs (raw_trans,
// RFLX, status) go through a registered XOR tree to one pin, so none of the
// logic behind them is optimized away. The serial line is on real pins. The
// pad chains cost about 1 LC per pad bit, as the external chips would on a
// board; the placed figures include them.
module uart_wrap #(
    parameter integer          NUM_PINS      = 64,
    parameter [NUM_PINS-1:0]   TIMER_MASK    = {NUM_PINS{1'b1}},
    parameter integer          PIN_ID_BASE   = 0,
    parameter integer          TIMER_ID_BASE = 0,
    parameter integer          TRANS_ID_BASE = 0,
    parameter integer          CLK_HZ        = 12_000_000,
    parameter integer          BAUD          = 115_200
) (
    input  wire clk,
    input  wire rst_i,        // reset request, synchronized here
    input  wire rx,
    output wire tx,
    input  wire pin_sin,      // pad levels, one bit a clock
    input  wire pin_load,     // 1: capture pin_o/pin_oe into the output chain
    output wire pin_sout,     // the output chain, one bit a clock
    output reg  aux_o         // XOR of every other output
);
    localparam integer NA = NUM_PINS + 1 + 6 + 16 + 3;  // raw_trans, rflx, link_up, frame_err, rx_overflow
    localparam integer L1 = (NA + 3) / 4;
    localparam integer L2 = (L1 + 3) / 4;

    reg [1:0]            rst_q;
    reg [1:0]            load_q;
    reg [NUM_PINS-1:0]   in_q;
    reg [2*NUM_PINS-1:0] out_q;
    reg [L1-1:0]         x1_q;
    reg [L2-1:0]         x2_q;

    wire [NUM_PINS-1:0] pin_o, pin_oe, raw_trans;
    wire                rflx_valid, link_up, frame_err, rx_overflow;
    wire [5:0]          rflx_id;
    wire [15:0]         rflx_data;
    // Zero-padded to whole groups of four (one more zero keeps the replication non-empty).
    wire [4*L1:0]       aux = {{4 * L1 - NA + 1{1'b0}}, raw_trans, rflx_valid, rflx_id, rflx_data,
                               link_up, frame_err, rx_overflow};
    wire [4*L2:0]       x1  = {{4 * L2 - L1 + 1{1'b0}}, x1_q};

    brainstem_dio_uart #(
        .CLK_HZ        (CLK_HZ),
        .BAUD          (BAUD),
        .NUM_PINS      (NUM_PINS),
        .TIMER_MASK    (TIMER_MASK),
        .PIN_ID_BASE   (PIN_ID_BASE),
        .TIMER_ID_BASE (TIMER_ID_BASE),
        .TRANS_ID_BASE (TRANS_ID_BASE)
    ) u_dio (
        .clk         (clk),
        .rst         (rst_q[1]),
        .rx          (rx),
        .tx          (tx),
        .pin_i       (in_q),
        .pin_o       (pin_o),
        .pin_oe      (pin_oe),
        .raw_trans   (raw_trans),
        .rflx_valid  (rflx_valid),
        .rflx_id     (rflx_id),
        .rflx_data   (rflx_data),
        .link_up     (link_up),
        .frame_err   (frame_err),
        .rx_overflow (rx_overflow)
    );

    integer i;
    always @(posedge clk) begin
        rst_q  <= {rst_q[0], rst_i};
        load_q <= {load_q[0], pin_load};
        in_q   <= {in_q[NUM_PINS-2:0], pin_sin};
        out_q  <= load_q[1] ? {pin_oe, pin_o} : {out_q[2*NUM_PINS-2:0], 1'b0};
        for (i = 0; i < L1; i = i + 1) x1_q[i] <= ^aux[4*i +: 4];
        for (i = 0; i < L2; i = i + 1) x2_q[i] <= ^x1[4*i +: 4];
        aux_o  <= ^x2_q;
    end
    assign pin_sout = out_q[2*NUM_PINS-1];
endmodule
`default_nettype wire
