// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A one-hot vector's set bit as a 6-bit number (0 when none is set): bit b
// of the number is the OR of the inputs whose index has bit b set, a word
// operation per bit and no loop over the inputs in simulation.
module bsd_onehot_idx #(
    parameter integer N = 4  // 1..64
) (
    input  wire [N-1:0] onehot_i,
    output wire [5:0]   idx_o
);
    // The inputs whose index has bit b set.
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [N-1:0] index_bit(input integer b);
        integer t;
        begin
            for (t = 0; t < N; t = t + 1) index_bit[t] = ((t >> b) & 1) != 0;
        end
    endfunction
    /* verilator coverage_on */

    genvar g;
    generate
        for (g = 0; g < 6; g = g + 1) begin : g_bit
            localparam [N-1:0] BITS = index_bit(g);
            assign idx_o[g] = |(onehot_i & BITS);
        end
    endgenerate
endmodule
`default_nettype wire
