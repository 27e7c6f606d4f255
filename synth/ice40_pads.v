// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// A bus of iCE40 pads for the digital pins (board glue: SB_IO is an iCE40
// primitive, so this file stays out of rtl/; tb/lib/pads/SB_IO.v models it for
// the tests). Pads 0..USED-1 carry pins: PIN_TYPE 1010_01, output enabled by
// OUTPUT_ENABLE, plain (unregistered) input, since the core synchronizes its
// pins itself. The others are spare: 0000_01, input only. Every pad has the
// internal pull-up on, so an unconnected input reads 1.
module ice40_pads #(
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
            localparam [5:0] TYPE = (p < USED) ? 6'b1010_01 : 6'b0000_01;
            SB_IO #(.PIN_TYPE(TYPE), .PULLUP(1'b1)) u_io (
                .PACKAGE_PIN(pad[p]), .OUTPUT_ENABLE(oe[p]), .D_OUT_0(o[p]), .D_IN_0(i[p]));
        end
    endgenerate
endmodule
`default_nettype wire
