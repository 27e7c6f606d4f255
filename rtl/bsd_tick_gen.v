// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Strobe at RATE_HZ on average from a CLK_HZ clock, with no drift.
// A phase accumulator adds RATE/g and wraps at CLK/g (g = gcd), so the
// strobe phase never strays more than one clock from the ideal grid, for any
// CLK_HZ, not only exact multiples of RATE_HZ. RATE_HZ = 0 strobes every clock.
// When RATE_HZ divides CLK_HZ (RATE/g = 1: a plain divider by MOD = CLK/g,
// e.g. the 10 kHz poll), a Galois LFSR counts instead of the accumulator: no
// adder, a flop a bit and one XOR; it starts at 1, holds x^k mod a primitive
// trinomial after k clocks and goes back to 1 from x^(MOD-1), the strobe's
// clock, so the strobes come exactly where the accumulator's would.
module bsd_tick_gen #(
    parameter integer CLK_HZ  = 48_000_000,
    parameter integer RATE_HZ = 625_000
) (
    input  wire clk,
    input  wire rst,
    output wire tick_o
);
    reg tick_q;
    assign tick_o = tick_q;

    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer gcd(input integer a, input integer b);
        integer x, y, t, i;
        begin
            x = a;
            y = b;
            // Euclid needs far fewer than 64 steps for 32-bit operands.
            for (i = 0; i < 64; i = i + 1) begin
                if (y != 0) begin
                    t = x % y;
                    x = y;
                    y = t;
                end
            end
            gcd = x;
        end
    endfunction
    /* verilator coverage_on */
    `include "bsd_lfsr.vh"

    // g = gcd(CLK, RATE) and the modulus CLK/g, which both counters below use.
    localparam integer G0   = gcd(CLK_HZ, RATE_HZ == 0 ? 1 : RATE_HZ);
    localparam integer MOD0 = CLK_HZ / G0;

    generate
        if (RATE_HZ == 0) begin : g_every_clock
            always @(posedge clk) begin
                tick_q <= 1'b1;
                if (rst) tick_q <= 1'b0;
            end
        end else if (RATE_HZ / G0 == 1) begin : g_lfsr
            localparam integer  LW       = lfsr_width(MOD0);
            localparam [31:0]   LFSR_P   = lfsr_poly(LW);
            localparam [31:0]   WRAP_POW = lfsr_pow(MOD0 - 1, LW, LFSR_P);
            localparam [LW-1:0] WRAP     = WRAP_POW[LW-1:0];
            localparam [LW-1:0] ONE      = 1;
            // (MOD0 = 1, RATE_HZ = CLK_HZ: WRAP is 1, so it strobes every clock)
            reg  [LW-1:0] lfsr_q;  // x^(clocks since the last strobe's) mod the trinomial
            wire          wrap = lfsr_q == WRAP;

            always @(posedge clk) begin
                // (tick_q first, and one write of lfsr_q: each flop is read
                // before it is written, so a simulator keeps no copy of it)
                tick_q <= wrap;
                // (back to 1 on the strobe's clock and in reset: one synchronous set/reset)
                if (rst || wrap) lfsr_q <= ONE;
                else lfsr_q <= {lfsr_q[LW-2:0], 1'b0} ^ ({LW{lfsr_q[LW-1]}} & LFSR_P[LW-1:0]);
                if (rst) tick_q <= 1'b0;
            end

`ifdef FORMAL
`include "bsd_tick_gen_lfsr_props.vh"
`endif
        end else begin : g_accumulator
            localparam integer INC = RATE_HZ / G0;
            localparam integer MOD = MOD0;
            // acc < MOD always, and the adder below works mod 2^W (acc + INC is
            // never formed beside it), so W holds MOD - 1 and no more.
            localparam integer W = MOD > 1 ? $clog2(MOD) : 1;
            localparam [W-1:0] INC_W = INC[W-1:0];
            localparam [W-1:0] MOD_W = MOD[W-1:0];

            localparam [W-1:0] TOP_W = MOD_W - INC_W;  // acc + INC wraps from here up

            // The wrap is decided on the accumulator itself (acc + INC >= MOD
            // is acc >= MOD - INC), so one adder, whose second operand is INC
            // or INC - MOD, makes the next value. (INC is 2 or more here.)
            reg  [W-1:0] acc_q;
            wire         wrap = acc_q >= TOP_W;

            always @(posedge clk) begin
                tick_q <= wrap;  // (before acc_q's write: read first, no copy kept)
                acc_q  <= acc_q + (wrap ? INC_W - MOD_W : INC_W);
                if (rst) begin
                    acc_q  <= {W{1'b0}};
                    tick_q <= 1'b0;
                end
            end

`ifdef FORMAL
`include "bsd_tick_gen_props.vh"
`endif

`ifndef SYNTHESIS
            initial begin
                if (RATE_HZ > CLK_HZ)
                    $fatal(1, "bsd_tick_gen: RATE_HZ = %0d must be at most CLK_HZ = %0d", RATE_HZ, CLK_HZ);
            end
`endif
        end
    endgenerate
endmodule
`default_nettype wire
