// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// 8N1 UART receiver. The line is synchronized by two flops, a start bit is
// confirmed at its middle (a low pulse shorter than about half a bit is a
// glitch and is ignored), then each bit is sampled at its middle. A byte
// whose stop bit reads 0 is dropped with a one-clock frame_err_o strobe, and
// the receiver then waits for the line to go idle (high) again, so a break
// (line held low) gives one error, not a stream of 0x00 bytes.
//
// Timing: rx_i reaches the state machine 2..3 clocks after it changes (two
// flops plus the clock phase); from the start bit's falling edge so seen,
// the samples fall DIV/2 + k * DIV clocks later (k = 0 start, 1..8 data,
// 9 stop), and valid_o / frame_err_o are set on the stop bit's sample edge.
// DIV = CLK_HZ / BAUD rounded to whole clocks (12 MHz / 115200: 104, the
// bit 0.16 % short; a sender up to about 4 % off either way is read right).
module bsd_uart_rx #(
    parameter integer CLK_HZ = 48_000_000,
    parameter integer BAUD   = 9600
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       rx_i,         // serial line, asynchronous to clk, idle high
    output wire [7:0] data_o,       // the byte of the latest valid_o
    output wire       valid_o,      // one-clock strobe: a good byte in data_o
    output wire       frame_err_o   // one-clock strobe: a byte with a bad stop bit was dropped
);
    localparam integer DIV  = (CLK_HZ + BAUD / 2) / BAUD;  // clocks per bit
    localparam integer HALF = DIV / 2;                     // start edge to mid start bit
    localparam integer CW   = $clog2(DIV < 2 ? 2 : DIV);  // >= 1 bit, so a bad DIV reaches the check
    localparam [CW-1:0] BIT_RELOAD  = DIV[CW-1:0] - 1'b1;
    localparam [CW-1:0] HALF_RELOAD = HALF[CW-1:0] - 1'b1;

    localparam [2:0] ST_IDLE  = 3'd0;  // wait for a falling edge
    localparam [2:0] ST_START = 3'd1;  // confirm the start bit at its middle
    localparam [2:0] ST_DATA  = 3'd2;  // 8 data bits, LSB first
    localparam [2:0] ST_STOP  = 3'd3;  // check the stop bit
    localparam [2:0] ST_BREAK = 3'd4;  // after a framing error: wait for idle

`ifndef SYNTHESIS
    initial begin
        // A start bit must be confirmed at least a few clocks after its edge.
        if (DIV < 8)
            $fatal(1, "bsd_uart_rx: CLK_HZ / BAUD = %0d / %0d = %0d clocks per bit, must be at least 8",
                   CLK_HZ, BAUD, DIV);
    end
`endif

    // Two-flop synchronizer, reset to the idle level so a reset never
    // looks like a start bit.
    reg meta_q;
    reg rx_q;

    reg [2:0]    state_q;
    reg [CW-1:0] cnt_q;    // clocks to the next sample point, minus 1
    reg [2:0]    bit_q;    // data bit being received
    reg [7:0]    shift_q;  // data bits so far, the newest in bit 7
    reg [7:0]    data_q;
    reg          valid_q;
    reg          frame_err_q;

    assign data_o      = data_q;
    assign valid_o     = valid_q;
    assign frame_err_o = frame_err_q;

    wire sample = (cnt_q == {CW{1'b0}});

    always @(posedge clk) begin
        meta_q      <= rx_i;
        rx_q        <= meta_q;
        valid_q     <= 1'b0;
        frame_err_q <= 1'b0;
        if (!sample) cnt_q <= cnt_q - 1'b1;

        case (state_q)
            ST_IDLE: begin
                if (!rx_q) begin
                    state_q <= ST_START;
                    cnt_q   <= HALF_RELOAD;
                end
            end
            ST_START: begin
                if (sample) begin
                    // Back high at the middle: only a glitch.
                    state_q <= rx_q ? ST_IDLE : ST_DATA;
                    cnt_q   <= BIT_RELOAD;
                    bit_q   <= 3'd0;
                end
            end
            ST_DATA: begin
                if (sample) begin
                    shift_q <= {rx_q, shift_q[7:1]};
                    bit_q   <= bit_q + 1'b1;
                    cnt_q   <= BIT_RELOAD;
                    if (bit_q == 3'd7) state_q <= ST_STOP;
                end
            end
            ST_STOP: begin
                if (sample) begin
                    if (rx_q) begin
                        data_q  <= shift_q;
                        valid_q <= 1'b1;
                        state_q <= ST_IDLE;
                    end else begin
                        frame_err_q <= 1'b1;
                        state_q     <= ST_BREAK;
                    end
                end
            end
            default: begin  // ST_BREAK
                if (rx_q) state_q <= ST_IDLE;
            end
        endcase

        if (rst) begin
            meta_q      <= 1'b1;
            rx_q        <= 1'b1;
            state_q     <= ST_IDLE;
            cnt_q       <= {CW{1'b0}};
            bit_q       <= 3'd0;
            shift_q     <= 8'd0;
            data_q      <= 8'd0;
            valid_q     <= 1'b0;
            frame_err_q <= 1'b0;
        end
    end

`ifdef FORMAL
`include "bsd_uart_rx_props.vh"
`endif
endmodule
`default_nettype wire
