// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Simulation model of the ECP5 bidirectional pad BB, for the board-top tests
// (synthesis uses the vendor cell; this file is never synthesized).
// T = 1: the pad is not driven. The input path reads the pad's own pull-up
// (set in ulx3s.lpf on the board) when it is not driven, and the driven level
// when it is: O never depends on the simulator's resolution of B, so Icarus and
// both simulators agree without a strength model.
module BB (
    input  wire I,
    input  wire T,
    output wire O,
    inout  wire B
);
    assign B = T ? 1'bz : I;
    assign O = T ? 1'b1 : I;
endmodule
`default_nettype wire
