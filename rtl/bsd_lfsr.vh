// SPDX-License-Identifier: Apache-2.0
// Galois LFSR arithmetic for the counters that need no adder (bsd_parser's idle timeout,
// bsd_tick_gen's divider), `include`d inside a module. A w-bit LFSR that starts at 1 and
// steps by a multiplication by x modulo a primitive trinomial x^w + p (one XOR) holds
// x^k mod it after k steps, distinct for k < 2^w - 1: a count is compared with the constant
// lfsr_pow(k, w, p). Only localparam initializers and formal properties call these: they run
// while elaborating, never in simulation, so they are outside coverage.
/* verilator coverage_off */
// A primitive trinomial's terms below x^w, for the widths 2..31 that have one; 0 for the others.
function [31:0] lfsr_poly(input integer w);
    case (w)
        2, 3, 4, 6, 7, 15, 22:  lfsr_poly = 32'h3;
        5, 11, 21, 29:          lfsr_poly = 32'h5;
        9:                      lfsr_poly = 32'h11;
        10, 17, 20, 25, 28, 31: lfsr_poly = 32'h9;
        18:                     lfsr_poly = 32'h81;
        23:                     lfsr_poly = 32'h21;
        default:                lfsr_poly = 32'h0;
    endcase
endfunction

// The least width (2 or more) with a trinomial whose period 2^w - 1 holds n states.
function integer lfsr_width(input integer n);
    begin
        lfsr_width = 2;
        while (lfsr_width < 31 &&
               (((64'd1 << lfsr_width) - 64'd1) < {32'd0, n} || lfsr_poly(lfsr_width) == 32'h0))
            lfsr_width = lfsr_width + 1;
    end
endfunction

// a * b modulo x^w + p.
function [31:0] lfsr_mul(input [31:0] a, input [31:0] b, input integer w, input [31:0] p);
    integer i;
    begin
        lfsr_mul = 32'd0;
        for (i = w - 1; i >= 0; i = i - 1) begin
            lfsr_mul = ((lfsr_mul << 1) & ((32'd1 << w) - 32'd1)) ^ (lfsr_mul[w-1] ? p : 32'd0);
            if (b[i]) lfsr_mul = lfsr_mul ^ a;
        end
    end
endfunction

// x^n modulo x^w + p (w >= 2).
function [31:0] lfsr_pow(input [31:0] n, input integer w, input [31:0] p);
    integer    i;
    reg [31:0] base;
    begin
        lfsr_pow = 32'd1;
        base     = 32'd2;
        for (i = 0; i < 32; i = i + 1) begin
            if (n[i]) lfsr_pow = lfsr_mul(lfsr_pow, base, w, p);
            base = lfsr_mul(base, base, w, p);
        end
    end
endfunction
/* verilator coverage_on */
