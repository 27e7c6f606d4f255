// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Tang Nano 9K (GW1NR-LV9QN88PC6/I5) board top for brainstem_dio_uart.
//   clk       27 MHz oscillator (pin 52)
//   uart_rx   from the BL702, the host's USB serial port (pin 18); uart_tx to it (pin 17)
//   io[7:0]   header pins 25, 26, 27, 28, 29, 30, 33, 34: digital pin p on io[p]
//   led_n[0]  link_up (the host answers heartbeats); the LEDs are active low
//   led_n[1]  serial activity (~50 ms after a frame in either direction)
//   led_n[4]  ~170 ms after a framing error or an RX overflow
//   led_n[5]  alive blink (the last eighth of every 1.24 s)
//   btn_n     S1 (pin 4, low when pressed): optional reset; the design resets itself
// The pads of the digital pins are Gowin IOBUF tristates (synth/gowin_pads.v);
// their pull-ups are set in tangnano9k.cst (PULL_MODE=UP), so an unconnected
// input reads 1. IOBUF is a Gowin primitive, so this file stays out of rtl/.
// CLK_HZ 27 MHz: 43.2 clocks per 1.6 us tick, exact on average (the tick generator's
// phase accumulator: 5 ticks every 216 clocks); 9600 baud = 2813 clocks per bit (0.01 % slow).
module tangnano9k_top #(
    parameter integer CLK_HZ   = 27_000_000,
    parameter integer BAUD     = 9600,
    parameter integer NUM_PINS = 5            // 1..8, GP 1.0 layout by default
) (
    input  wire       clk,
    input  wire       uart_rx,
    output wire       uart_tx,
    input  wire       btn_n,
    output wire [5:0] led_n,
    inout  wire [7:0] io
);
    wire rst, link_up, frame_err, rx_overflow, act, err, alive;
    wire [NUM_PINS-1:0] pin_i, pin_o, pin_oe, raw_trans;
    wire                rflx_valid;
    wire [5:0]          rflx_id;
    wire [15:0]         rflx_data;

    board_status #(.CLK_HZ(CLK_HZ)) u_status (
        .clk         (clk),
        .btn_n       (btn_n),
        .rx          (uart_rx),
        .tx          (uart_tx),
        .frame_err   (frame_err),
        .rx_overflow (rx_overflow),
        .rst         (rst),
        .act         (act),
        .err         (err),
        .alive       (alive)
    );

    brainstem_dio_uart #(
        .CLK_HZ   (CLK_HZ),
        .BAUD     (BAUD),
        .NUM_PINS (NUM_PINS)
    ) u_dio (
        .clk         (clk),
        .rst         (rst),
        .rx          (uart_rx),
        .tx          (uart_tx),
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
    // Pin p on io[p]; header pins above NUM_PINS are spare inputs.
    // (One bit wider than the header, so the zero fill is never empty.)
    wire [8:0] o_w  = {{9 - NUM_PINS{1'b0}}, pin_o};
    wire [8:0] oe_w = {{9 - NUM_PINS{1'b0}}, pin_oe};
    wire [7:0] pad_i;
    gowin_pads #(.WIDTH(8), .USED(NUM_PINS)) u_pads (
        .pad(io), .o(o_w[7:0]), .oe(oe_w[7:0]), .i(pad_i));
    assign pin_i = pad_i[NUM_PINS-1:0];
    wire unused_pads = ^{o_w[8], oe_w[8], pad_i};

    assign led_n = ~{alive, err, 2'b00, act, link_up};
endmodule
`default_nettype wire
