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
// The pads of the digital pins are Gowin IOBUF tristates; their pull-ups are set
// in tangnano9k.cst (PULL_MODE=UP), so an unconnected input reads 1. IOBUF is a
// Gowin primitive, so this file stays out of rtl/ (tb/lib/pads/IOBUF.v models it for the tests).
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
    genvar p;
    generate
        for (p = 0; p < 8; p = p + 1) begin : g_pad
            wire din;
            if (p < NUM_PINS) begin : g_pin
                // OEN = 1: not driven. Plain input; the core synchronizes pin_i.
                IOBUF u_io (.I(pin_o[p]), .OEN(!pin_oe[p]), .O(din), .IO(io[p]));
                assign pin_i[p] = din;
            end else begin : g_spare
                // Spare header pins: inputs with the pull-up, never driven.
                IOBUF u_io (.I(1'b0), .OEN(1'b1), .O(din), .IO(io[p]));
                wire unused_din = din;
            end
        end
    endgenerate

    assign led_n = ~{alive, err, 2'b00, act, link_up};
endmodule
`default_nettype wire
