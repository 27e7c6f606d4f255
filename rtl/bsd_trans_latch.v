// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// One pin's one-shot transition latch (DIGCFG ENA/TRG).
// Arming loads the current level as the previous sample, so a level that is
// already present never fires by itself; an arm on the same clock as a
// matching edge wins (the edge becomes the new baseline).
module bsd_trans_latch (
    input  wire clk,
    input  wire rst,
    input  wire arm_i,     // DIG_CFG set, DIG_RST, or the power-up arm
    input  wire ena_i,     // DIGCFG ENA
    input  wire trg_i,     // DIGCFG TRG: 1 fires on 0->1, 0 on 1->0
    input  wire input_i,   // DIGCFG IODIR: the latch only watches inputs
    input  wire sample_i,  // POLL_HZ strobe
    input  wire level_i,   // synchronized pad level
    output wire fire_o     // one-clock pulse
);
    reg armed_q;
    reg prev_q;   // meaningful only while armed (an arm loads it): no reset
    reg fire_q;

    wire active = armed_q && ena_i && input_i && sample_i;
    // A change from the previous sample to the TRG level.
    wire hit    = (level_i == trg_i) && (prev_q != trg_i);
    wire fire   = active && hit;

    assign fire_o = fire_q;

    always @(posedge clk) begin
        fire_q  <= fire && !arm_i;
        armed_q <= arm_i || (armed_q && !fire);
        if (arm_i || active) prev_q <= level_i;
        if (rst) begin
            armed_q <= 1'b0;
            fire_q  <= 1'b0;
        end
    end

`ifdef FORMAL
`include "bsd_trans_latch_props.vh"
`endif
endmodule
`default_nettype wire
