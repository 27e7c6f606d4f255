// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// 8N1 UART transmitter with an AXI-Stream-style byte input. A byte is taken
// while the line is idle or on the last clock of the previous stop bit, so
// bytes offered back to back leave at the full line rate (10 bit times per
// byte, no idle clock between frames). tx_o and s_axis_tready come straight
// from flops, so the source's handshake logic starts at a register.
// The bit period is CLK_HZ / BAUD rounded to whole clocks.
module bsd_uart_tx #(
    parameter integer CLK_HZ = 48_000_000,
    parameter integer BAUD   = 9600
) (
    input  wire       clk,
    input  wire       rst,
    input  wire [7:0] s_axis_tdata,
    input  wire       s_axis_tvalid,
    output wire       s_axis_tready,
    output wire       tx_o           // serial line, idle high
);
    localparam integer DIV = (CLK_HZ + BAUD / 2) / BAUD;  // clocks per bit
    localparam integer CW  = $clog2(DIV < 2 ? 2 : DIV);  // >= 1 bit, so a bad DIV reaches the check
    localparam [CW-1:0] BIT_RELOAD = DIV[CW-1:0] - 1'b1;

`ifndef SYNTHESIS
    initial begin
        if (DIV < 2)
            $fatal(1, "bsd_uart_tx: CLK_HZ / BAUD = %0d / %0d = %0d clocks per bit, must be at least 2",
                   CLK_HZ, BAUD, DIV);
    end
`endif

    reg [8:0]    shift_q;  // bits after the one on the line: data, then stop
    reg [3:0]    left_q;   // bits still to send, the one on the line included; 0 = idle
    reg [CW-1:0] cnt_q;    // clocks left in the current bit, minus 1
    // Always equal to (idle || last clock of the stop bit), computed a clock
    // ahead from the next values of left_q and cnt_q.
    reg          ready_q;
    reg          tx_q;

    assign tx_o = tx_q;

    localparam [CW-1:0] CNT_ONE = {{(CW - 1){1'b0}}, 1'b1};

    wire bit_end = (cnt_q == {CW{1'b0}});
    wire busy    = (left_q != 4'd0);

    assign s_axis_tready = ready_q;

    always @(posedge clk) begin
        if (busy) begin
            if (bit_end) begin
                tx_q    <= shift_q[0];
                shift_q <= {1'b1, shift_q[8:1]};
                left_q  <= left_q - 1'b1;
                cnt_q   <= BIT_RELOAD;
                // Next: idle, or a bit of DIV >= 2 clocks that is not its end.
                ready_q <= (left_q == 4'd1);
            end else begin
                cnt_q   <= cnt_q - 1'b1;
                ready_q <= (left_q == 4'd1) && (cnt_q == CNT_ONE);
            end
        end
        if (s_axis_tvalid && s_axis_tready) begin
            tx_q    <= 1'b0;  // start bit
            shift_q <= {1'b1, s_axis_tdata};
            left_q  <= 4'd10;
            cnt_q   <= BIT_RELOAD;
            ready_q <= 1'b0;
        end
        if (rst) begin
            tx_q    <= 1'b1;
            shift_q <= 9'h1FF;
            left_q  <= 4'd0;
            cnt_q   <= {CW{1'b0}};
            ready_q <= 1'b1;
        end
    end

`ifdef FORMAL
`include "bsd_uart_tx_props.vh"
`endif
endmodule
`default_nettype wire
