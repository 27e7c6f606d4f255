// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A bus of ECP5 pads for the digital pins (board glue: BB is an ECP5
// primitive, so this file stays out of rtl/; tb/lib/pads/BB.v models it for
// the tests). Pads 0..USED-1 carry pins: BB tristates, plain input, since the
// core synchronizes its pins itself. The others are spare: inputs, never
// driven. Pull-ups are set in the board's constraints file.
module ecp5_pads #(
    parameter integer WIDTH = 8,
    parameter integer USED  = 8      // 0..WIDTH
) (
    inout  wire [WIDTH-1:0] pad,
    input  wire [WIDTH-1:0] o,       // level driven ...
    input  wire [WIDTH-1:0] oe,      // ... while 1 (spare pads: ignored)
    output wire [WIDTH-1:0] i        // the pad's level
);
    genvar p;
    generate
        for (p = 0; p < WIDTH; p = p + 1) begin : g_pad
            if (p < USED) begin : g_pin
                // T = 1: not driven.
                BB u_io (.I(o[p]), .T(!oe[p]), .O(i[p]), .B(pad[p]));
            end else begin : g_spare
                BB u_io (.I(1'b0), .T(1'b1), .O(i[p]), .B(pad[p]));
                wire unused_spare = ^{o[p], oe[p]};
            end
        end
    endgenerate
endmodule
`default_nettype wire
