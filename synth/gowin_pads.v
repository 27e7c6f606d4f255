// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A bus of Gowin pads for the digital pins (board glue: IOBUF is a Gowin
// primitive, so this file stays out of rtl/; tb/lib/pads/IOBUF.v models it
// for the tests). Pads 0..USED-1 carry pins: IOBUF tristates, plain input,
// since the core synchronizes its pins itself. The others are spare: inputs,
// never driven. Pull-ups are set in the board's constraints file.
module gowin_pads #(
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
                // OEN = 1: not driven.
                IOBUF u_io (.I(o[p]), .OEN(!oe[p]), .O(i[p]), .IO(pad[p]));
            end else begin : g_spare
                IOBUF u_io (.I(1'b0), .OEN(1'b1), .O(i[p]), .IO(pad[p]));
                wire unused_spare = ^{o[p], oe[p]};
            end
        end
    endgenerate
endmodule
`default_nettype wire
