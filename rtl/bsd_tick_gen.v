// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Strobe at RATE_HZ on average from a CLK_HZ clock, with no drift.
// A phase accumulator adds RATE/g and wraps at CLK/g (g = gcd), so the
// strobe phase never strays more than one clock from the ideal grid, for any
// CLK_HZ, not only exact multiples of RATE_HZ. RATE_HZ = 0 strobes every clock.
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

    generate
        if (RATE_HZ == 0) begin : g_every_clock
            always @(posedge clk) begin
                tick_q <= 1'b1;
                if (rst) tick_q <= 1'b0;
            end
        end else begin : g_accumulator
            localparam integer G   = gcd(CLK_HZ, RATE_HZ);
            localparam integer INC = RATE_HZ / G;
            localparam integer MOD = CLK_HZ / G;
            // acc < MOD always, and the adder below works mod 2^W (acc + INC is
            // never formed beside it), so W holds MOD - 1 and no more.
            localparam integer W = MOD > 1 ? $clog2(MOD) : 1;
            localparam [W-1:0] INC_W = INC[W-1:0];
            localparam [W-1:0] MOD_W = MOD[W-1:0];

            localparam [W-1:0] TOP_W = MOD_W - INC_W;  // acc + INC wraps from here up

            // The wrap is decided on the accumulator itself (acc + INC >= MOD
            // is acc >= MOD - INC), so one adder, whose second operand is INC
            // or INC - MOD, makes the next value. With INC = 1 the wrap is
            // acc = MOD - 1, the one value below MOD with all of its 1 bits.
            reg  [W-1:0] acc_q;
            wire         wrap = INC == 1 ? &(acc_q | ~TOP_W) : acc_q >= TOP_W;

            always @(posedge clk) begin
                acc_q  <= acc_q + (wrap ? INC_W - MOD_W : INC_W);
                tick_q <= wrap;
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
