// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// ULX3S (LFE5U-85F-6BG381C) board top for brainstem_dio_uart.
//   clk_25mhz  25 MHz oscillator (G2)
//   ftdi_txd   from the FT231X, the host's serial port (M1); ftdi_rxd to it (L4)
//   gp[7:0]    header J1, the "+" row, J1_5+ .. J1_23+: digital pin p on gp[p]
//   led[0]     link_up (the host answers heartbeats)
//   led[1]     serial activity (~50 ms after a frame in either direction)
//   led[6]     ~170 ms after a framing error or an RX overflow
//   led[7]     alive blink (the last eighth of every 1.34 s)
//   btn_pwr_n  BTN_PWR (D6, low when pressed): optional reset; the design resets itself
//   wifi_gpio0 held high, so the ESP32 stays out of its boot loader
// The pads of the digital pins are ECP5 BB tristates (synth/ecp5_pads.v); their
// pull-ups are set in ulx3s.lpf (PULLMODE=UP), so an unconnected input reads 1.
// BB is an ECP5 primitive, so this file stays out of rtl/.
// CLK_HZ 25 MHz: 40 clocks per 1.6 us tick, exact; 9600 baud = 2604 clocks per bit (0.006 % fast).
module ulx3s_top #(
    parameter integer CLK_HZ   = 25_000_000,
    parameter integer BAUD     = 9600,
    parameter integer NUM_PINS = 5            // 1..8, GP 1.0 layout by default
) (
    input  wire       clk_25mhz,
    input  wire       ftdi_txd,
    output wire       ftdi_rxd,
    input  wire       btn_pwr_n,
    output wire [7:0] led,
    output wire       wifi_gpio0,
    inout  wire [7:0] gp
);
    wire rst, link_up, frame_err, rx_overflow, act, err, alive;
    wire [NUM_PINS-1:0] pin_i, pin_o, pin_oe, raw_trans;
    wire                rflx_valid;
    wire [5:0]          rflx_id;
    wire [15:0]         rflx_data;

    board_status #(.CLK_HZ(CLK_HZ)) u_status (
        .clk         (clk_25mhz),
        .btn_n       (btn_pwr_n),
        .rx          (ftdi_txd),
        .tx          (ftdi_rxd),
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
        .clk         (clk_25mhz),
        .rst         (rst),
        .rx          (ftdi_txd),
        .tx          (ftdi_rxd),
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
    // Pin p on gp[p]; header pins above NUM_PINS are spare inputs.
    // (One bit wider than the header, so the zero fill is never empty.)
    wire [8:0] o_w  = {{9 - NUM_PINS{1'b0}}, pin_o};
    wire [8:0] oe_w = {{9 - NUM_PINS{1'b0}}, pin_oe};
    wire [7:0] pad_i;
    ecp5_pads #(.WIDTH(8), .USED(NUM_PINS)) u_pads (
        .pad(gp), .o(o_w[7:0]), .oe(oe_w[7:0]), .i(pad_i));
    assign pin_i = pad_i[NUM_PINS-1:0];
    wire unused_pads = ^{o_w[8], oe_w[8], pad_i};

    assign led        = {alive, err, 4'b0000, act, link_up};
    assign wifi_gpio0 = 1'b1;
endmodule
`default_nettype wire
