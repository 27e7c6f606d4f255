// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Board-level glue shared by the ULX3S and Tang Nano 9K tops (synth/*_top.v):
// the power-up reset and the status LEDs. Plain RTL, no vendor primitive.
//   rst       1 for 16 clocks after configuration (flops are 0 after it on
//             ECP5 and Gowin, as on iCE40), and while btn_n (synchronized) is low
//   act       lit for ~50 ms after any low level on the serial lines (a frame
//             in either direction): the activity LED
//   err       lit for ~170 ms after a framing error or an RX overflow
//   alive     the last eighth of a 2^ceil(log2(CLK_HZ)) clock period (1-2.7 s)
module board_status #(
    parameter integer CLK_HZ = 25_000_000
) (
    input  wire clk,
    input  wire btn_n,        // active-low reset button (asynchronous)
    input  wire rx,           // the serial lines, host -> module (asynchronous) ...
    input  wire tx,           // ... and module -> host
    input  wire frame_err,
    input  wire rx_overflow,
    output wire rst,
    output wire act,
    output wire err,
    output wire alive
);
    localparam integer ACT_CLKS = CLK_HZ / 20;       // 50 ms
    localparam integer ERR_CLKS = CLK_HZ / 6;        // ~170 ms
    localparam integer ACT_W    = $clog2(ACT_CLKS + 1);
    localparam integer ERR_W    = $clog2(ERR_CLKS + 1);
    localparam integer BLINK_W  = $clog2(CLK_HZ);

    // -------------------------------------------------- power-up reset
    // rst comes straight from a flop (run_q, 0 after configuration): it reaches
    // nearly every flop of the module.
    reg [1:0] btn_q = 2'b11;
    reg [3:0] por_q = 4'd0;
    reg       run_q = 1'b0;
    always @(posedge clk) begin
        btn_q <= {btn_q[0], btn_n};
        if (por_q != 4'hF) por_q <= por_q + 1'b1;
        if (!btn_q[1]) por_q <= 4'd0;
        run_q <= (por_q == 4'hF) && btn_q[1];
    end
    assign rst = !run_q;

    // -------------------------------------------------- LEDs
    reg [1:0]         line_q  = 2'b11;   // rx, tx through one flop each (an LED needs no more)
    reg [ACT_W-1:0]   act_q   = {ACT_W{1'b0}};
    reg [ERR_W-1:0]   err_q   = {ERR_W{1'b0}};
    reg [BLINK_W-1:0] blink_q = {BLINK_W{1'b0}};
    always @(posedge clk) begin
        line_q  <= {rx, tx};
        blink_q <= blink_q + 1'b1;
        if (act_q != {ACT_W{1'b0}}) act_q <= act_q - 1'b1;
        if (line_q != 2'b11) act_q <= ACT_CLKS[ACT_W-1:0];
        if (err_q != {ERR_W{1'b0}}) err_q <= err_q - 1'b1;
        if (frame_err || rx_overflow) err_q <= ERR_CLKS[ERR_W-1:0];
        if (rst) err_q <= {ERR_W{1'b0}};
    end
    assign act   = act_q != {ACT_W{1'b0}};
    assign err   = err_q != {ERR_W{1'b0}};
    assign alive = &blink_q[BLINK_W-1:BLINK_W-3];
endmodule
`default_nettype wire
