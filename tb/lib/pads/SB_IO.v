// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Simulation model of the iCE40 pad SB_IO as icebreaker_top uses it (PIN_TYPE
// 1010_01 or 0000_01: unregistered input, output enabled by OUTPUT_ENABLE or
// never; PULLUP), for the board-top tests; synthesis uses the vendor cell.
// The input path reads `ext` (the pull-up level unless a test sets it) when the
// pad is not driven and the driven level when it is: D_IN_0 never depends on the
// simulator's resolution of PACKAGE_PIN, so Icarus and Verilator agree.
module SB_IO #(
    parameter [5:0] PIN_TYPE = 6'b0000_01,
    parameter [0:0] PULLUP   = 1'b0
) (
    inout  wire PACKAGE_PIN,
    input  wire OUTPUT_ENABLE,
    input  wire D_OUT_0,
    output wire D_IN_0
);
    // Only the types icebreaker_top uses: output 10 (tristate, enabled by
    // OUTPUT_ENABLE) or 00 (none), input 01 (plain).
    // ext: what holds the pin when the FPGA does not drive it, the pull-up level (PULLUP;
    // else 0) until a test deposits another one (a sensor pulling the pin low).
    reg  ext = PULLUP;
    wire drive = (PIN_TYPE[5:4] == 2'b10) && OUTPUT_ENABLE;
    assign PACKAGE_PIN = drive ? D_OUT_0 : 1'bz;
    assign D_IN_0      = drive ? D_OUT_0 : ext;
    initial begin
        if (PIN_TYPE[1:0] != 2'b01 || (PIN_TYPE[5:4] != 2'b10 && PIN_TYPE[5:4] != 2'b00)) begin
            $display("SB_IO model: PIN_TYPE %b is not modelled", PIN_TYPE);
            $finish;
        end
    end
endmodule
`default_nettype wire
