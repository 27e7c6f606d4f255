// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The one-shot transition latches (DIGCFG ENA/TRG) of WIDTH pins, bit i
// being pin i's. Arming loads the current level as the previous sample, so
// a level that is already present never fires by itself; an arm on the same
// clock as a matching edge wins (the edge becomes the new baseline). All pins
// are one set of vector operations rather than an instance per pin: a model
// built by Verilator then works on a few words a clock, not on every pin's bits.
module bsd_trans_latch #(
    parameter integer WIDTH = 1
) (
    input  wire             clk,
    input  wire             rst,
    input  wire [WIDTH-1:0] arm_i,     // DIG_CFG set, DIG_RST, or the power-up arm
    input  wire [WIDTH-1:0] ena_i,     // DIGCFG ENA
    input  wire [WIDTH-1:0] trg_i,     // DIGCFG TRG: 1 fires on 0->1, 0 on 1->0
    input  wire [WIDTH-1:0] input_i,   // DIGCFG IODIR: the latch only watches inputs
    input  wire             sample_i,  // POLL_HZ strobe, common to all pins
    input  wire [WIDTH-1:0] level_i,   // synchronized pad levels
    output wire [WIDTH-1:0] fire_o     // one-clock pulses
);
    reg [WIDTH-1:0] armed_q;
    reg [WIDTH-1:0] prev_q;   // meaningful only while armed (an arm loads it): no reset
    reg [WIDTH-1:0] fire_q;

    wire [WIDTH-1:0] active = armed_q & ena_i & input_i & {WIDTH{sample_i}};
    // A change from the previous sample to the TRG level.
    wire [WIDTH-1:0] hit    = ~(level_i ^ trg_i) & (prev_q ^ trg_i);
    wire [WIDTH-1:0] fire   = active & hit;
    wire [WIDTH-1:0] load   = arm_i | active;

    assign fire_o = fire_q;

    always @(posedge clk) begin
        fire_q  <= fire & ~arm_i;
        armed_q <= arm_i | (armed_q & ~fire);
        prev_q  <= (load & level_i) | (~load & prev_q);
        if (rst) begin
            armed_q <= {WIDTH{1'b0}};
            fire_q  <= {WIDTH{1'b0}};
        end
    end

`ifdef FORMAL
`include "bsd_trans_latch_props.vh"
`endif
endmodule
`default_nettype wire
