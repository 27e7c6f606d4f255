// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A 6-bit timer number (en_i: or none) as a one-hot vector: the block of 8
// (a byte shifted by 8 x idx[5:3]) AND the bit in each block, so synthesis
// sees two 8-way decoders and a gate per output, and simulation a few word
// operations (not a statement per bit).
// Numbers at or above N select nothing.
module bsd_idx_onehot #(
    parameter integer N = 4  // 1..64
) (
    input  wire         en_i,
    input  wire [5:0]   idx_i,
    output wire [N-1:0] onehot_o
);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [63:0] full = ({64{en_i}} & (64'hFF << {idx_i[5:3], 3'b000})) &
                       (64'h0101_0101_0101_0101 << idx_i[2:0]);  // N < 64: bits N.. unused
    /* verilator lint_on UNUSEDSIGNAL */
    assign onehot_o = full[N-1:0];
endmodule
`default_nettype wire
