// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Simulation model of the Gowin bidirectional pad IOBUF, for the board-top tests
// (synthesis uses the vendor cell; this file is never synthesized).
// OEN = 1: the pad is not driven. The input path reads the pad's own pull-up
// (set in tangnano9k.cst on the board) when it is not driven, and the driven
// level when it is: O never depends on the simulator's resolution of IO, so
// both simulators agree without a strength model.
module IOBUF (
    input  wire I,
    input  wire OEN,
    output wire O,
    inout  wire IO
);
    assign IO = OEN ? 1'bz : I;
    assign O  = OEN ? 1'b1 : I;
endmodule
`default_nettype wire
