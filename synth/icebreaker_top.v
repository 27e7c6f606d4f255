// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// iCEBreaker (iCE40UP5K-SG48) board top for brainstem_dio_uart.
//   CLK     12 MHz oscillator (pin 35)
//   RX, TX  the FTDI's second channel, the host's serial port (pins 6, 9)
//   P1A     PMOD 1A: digital pins 0..7 on P1A1, P1A2, P1A3, P1A4, P1A7, ..., P1A10
//   P1B     PMOD 1B: digital pins 8..15, in the same order
//   P2      PMOD 2: digital pins 16..23, in the same order
//   LEDG_N  link_up (the host answers heartbeats)
//   LEDR_N  alive blink (1/8 of each ~1.4 s); lit ~170 ms after a framing error or RX overflow
//   BTN_N   optional reset; the design resets itself at power-up
// The pads of the digital pins are SB_IO tristates with the internal pull-up
// on (synth/ice40_pads.v), so an unconnected input reads 1; PMOD pins above
// NUM_PINS are inputs with the pull-up. NUM_PINS 24 with TIMER_MASK
// 24'hFFFFFF puts a timer on every PMOD pin (make bitstream
// BOARD=icebreaker24). This file instantiates iCE40 primitives and is
// therefore kept out of rtl/ (the simulators build rtl/*.v).
module icebreaker_top #(
    parameter integer CLK_HZ   = 12_000_000,
    parameter integer BAUD     = 9600,
    parameter integer NUM_PINS = 5,           // 1..24, GP 1.0 layout by default
    parameter [NUM_PINS-1:0] TIMER_MASK = 5'b11110
) (
    input  wire       CLK,
    input  wire       RX,
    output wire       TX,
    input  wire       BTN_N,
    output wire       LEDR_N,
    output wire       LEDG_N,
    inout  wire [7:0] P1A,
    inout  wire [7:0] P1B,
    inout  wire [7:0] P2
);
    // -------------------------------------------------- power-up reset
    // iCE40 flops are 0 after configuration: rst stays 1 for 16 clocks after
    // power-up, and again after BTN_N (synchronized) is pressed. rst comes
    // straight from a flop (run_q, 0 after configuration), since it reaches
    // nearly every flop and the core's s_axis_tready.
    reg [1:0] btn_q = 2'b11;
    reg [3:0] por_q = 4'd0;
    reg       run_q = 1'b0;
    always @(posedge CLK) begin
        btn_q <= {btn_q[0], BTN_N};
        if (por_q != 4'hF) por_q <= por_q + 1'b1;
        if (!btn_q[1]) por_q <= 4'd0;
        run_q <= (por_q == 4'hF) && btn_q[1];
    end
    wire rst = !run_q;

    // -------------------------------------------------- the module
    wire [NUM_PINS-1:0] pin_i, pin_o, pin_oe, raw_trans;
    wire                rflx_valid;
    wire [5:0]          rflx_id;
    wire [15:0]         rflx_data;
    wire                link_up, frame_err, rx_overflow;

    brainstem_dio_uart #(
        .CLK_HZ   (CLK_HZ),
        .BAUD     (BAUD),
        .NUM_PINS   (NUM_PINS),
        .TIMER_MASK (TIMER_MASK)
    ) u_dio (
        .clk         (CLK),
        .rst         (rst),
        .rx          (RX),
        .tx          (TX),
        .pin_i       (pin_i),
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

    // No on-board program listens to RFLX values or raw transitions here.
    wire unused_dio = ^{raw_trans, rflx_valid, rflx_id, rflx_data};

    // -------------------------------------------------- pads
    // Pin p is on PMOD p / 8 (synth/ice40_pads.v); PMOD pins above NUM_PINS
    // are spare inputs.
    localparam integer USED_1A = NUM_PINS < 8 ? NUM_PINS : 8;
    localparam integer USED_1B = NUM_PINS < 8 ? 0 : NUM_PINS < 16 ? NUM_PINS - 8 : 8;
    localparam integer USED_2  = NUM_PINS < 16 ? 0 : NUM_PINS - 16;
    wire [24:0] oe_w = {{25 - NUM_PINS{1'b0}}, pin_oe};
    wire [24:0] o_w  = {{25 - NUM_PINS{1'b0}}, pin_o};
    wire [23:0] din;

    ice40_pads #(.WIDTH(8), .USED(USED_1A)) u_p1a (
        .pad(P1A), .o(o_w[7:0]), .oe(oe_w[7:0]), .i(din[7:0]));
    ice40_pads #(.WIDTH(8), .USED(USED_1B)) u_p1b (
        .pad(P1B), .o(o_w[15:8]), .oe(oe_w[15:8]), .i(din[15:8]));
    ice40_pads #(.WIDTH(8), .USED(USED_2)) u_p2 (
        .pad(P2), .o(o_w[23:16]), .oe(oe_w[23:16]), .i(din[23:16]));
    assign pin_i = din[NUM_PINS-1:0];
    wire unused_pads = ^{oe_w[24], o_w[24], din};

    // -------------------------------------------------- LEDs
    // 2^24 clocks = 1.4 s at 12 MHz; the red LED is on for its last eighth.
    // err_q[21] is the red light after an error: it counts down from 22'h3F_FFFF
    // while bit 21 is set, so it is lit for 2^21 clocks (~170 ms), and the
    // count's enable is that one flop, not a compare of all 22 bits.
    reg [23:0] blink_q = 24'd0;
    reg [21:0] err_q   = 22'd0;
    always @(posedge CLK) begin
        blink_q <= blink_q + 1'b1;
        if (err_q[21]) err_q <= err_q - 1'b1;
        if (frame_err || rx_overflow) err_q <= 22'h3F_FFFF;
        if (rst) err_q <= 22'd0;
    end

    assign LEDG_N = !link_up;
    assign LEDR_N = !((&blink_q[23:21]) || err_q[21]);
endmodule
`default_nettype wire
