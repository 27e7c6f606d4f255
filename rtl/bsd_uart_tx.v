// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// 8N1 UART transmitter with an AXI-Stream-style byte input. A byte is taken
// while the line is idle or on the last clock of the previous stop bit, so
// bytes offered back to back leave at the full line rate (10 bit times per
// byte, no idle clock between frames). tx_o and s_axis_tready come straight
// from flops, so the source's handshake logic starts at a register.
// The bit period is CLK_HZ / BAUD rounded to whole clocks. The clocks of a
// bit are counted by a Galois LFSR (rtl/bsd_lfsr.vh), not a down-counter: at
// 12 MHz / 9600 an 11-bit decrement is a carry chain that nextpnr split into
// three, and its zero test fed its own reload (the iCEBreaker top's critical
// path); an LFSR step is a gate a bit, and the bit's end is a flop set by one
// compare with a constant on the clock before.
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

`ifndef SYNTHESIS
    initial begin
        if (DIV < 2)
            $fatal(1, "bsd_uart_tx: CLK_HZ / BAUD = %0d / %0d = %0d clocks per bit, must be at least 2",
                   CLK_HZ, BAUD, DIV);
    end
`endif

    `include "bsd_lfsr.vh"
    // The LFSR starts a bit at 1 and holds x^k after k clocks of it: the bit's
    // last clock is x^(DIV-1), the one before it x^(DIV-2) (DIV >= 2).
    localparam integer  LW        = lfsr_width(DIV < 2 ? 2 : DIV);
    localparam [31:0]   LFSR_P    = lfsr_poly(LW);
    localparam [31:0]   PEN_POW   = lfsr_pow(DIV < 2 ? 0 : DIV - 2, LW, LFSR_P);
    localparam [LW-1:0] PENULT    = PEN_POW[LW-1:0];
    localparam [LW-1:0] ONE       = 1;

    reg [8:0]    shift_q;  // bits after the one on the line: data, then stop
    reg [3:0]    left_q;   // bits still to send, the one on the line included; 0 = idle
    reg [LW-1:0] cnt_q;    // x^(clocks of the current bit so far) mod the trinomial
    reg          end_q;    // the current bit's last clock (cnt_q == x^(DIV-1))
    // Always equal to (idle || last clock of the stop bit), computed a clock
    // ahead from the next values of left_q and end_q.
    reg          ready_q;
    reg          tx_q;

    assign tx_o = tx_q;

    wire bit_end = end_q;
    wire busy    = (left_q != 4'd0);
    // The next clock is the bit's last (read only while not at its end).
    wire penult  = (cnt_q == PENULT);

    assign s_axis_tready = ready_q;

    always @(posedge clk) begin
        if (busy) begin
            if (bit_end) begin
                tx_q    <= shift_q[0];
                shift_q <= {1'b1, shift_q[8:1]};
                left_q  <= left_q - 1'b1;
                cnt_q   <= ONE;
                end_q   <= 1'b0;
                // Next: idle, or a bit of DIV >= 2 clocks that is not its end.
                ready_q <= (left_q == 4'd1);
            end else begin
                cnt_q   <= {cnt_q[LW-2:0], 1'b0} ^ ({LW{cnt_q[LW-1]}} & LFSR_P[LW-1:0]);
                end_q   <= penult;
                ready_q <= (left_q == 4'd1) && penult;
            end
        end
        if (s_axis_tvalid && s_axis_tready) begin
            tx_q    <= 1'b0;  // start bit
            shift_q <= {1'b1, s_axis_tdata};
            left_q  <= 4'd10;
            cnt_q   <= ONE;
            end_q   <= 1'b0;
            ready_q <= 1'b0;
        end
        if (rst) begin
            tx_q    <= 1'b1;
            shift_q <= 9'h1FF;
            left_q  <= 4'd0;
            cnt_q   <= ONE;
            end_q   <= 1'b0;
            ready_q <= 1'b1;
        end
    end

`ifdef FORMAL
`include "bsd_uart_tx_props.vh"
`endif
endmodule
`default_nettype wire
