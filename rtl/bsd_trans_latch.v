// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The one-shot transition latches (DIGCFG ENA/TRG) of WIDTH pins, bit i
// being pin i's. Arming loads the current level as the previous sample, so
// a level that is already present never fires by itself; an arm on the same
// clock as a matching edge wins (the edge becomes the new baseline). All pins
// are one set of vector operations rather than an instance per pin: a model
// built by Verilator then works on a few words a clock, not on every pin's bits.
// A pin is watched on one bit, ENA && IODIR (bsd_cfg_regs keeps it), and
// the sample is part of the edge test (hit): the flops then take a LUT4
// each and the edge test a fourth, where the two bits took five. The
// previous level is loaded on every sample and every arm,
// watched or not: it matters only while armed and watched, and watch_i
// changes only with an arm (a DIG_CFG write re-arms its pin), so a plain
// load a bit, sample or arm, is the same there. Its data is then a LUT of
// four (sample, arm, level, itself) that nextpnr packs with the flop, where
// an enable of armed, watch, arm and sample took a LUT and left the flop a
// logic cell alone (64 pins: 64 cells fewer).
module bsd_trans_latch #(
    parameter integer WIDTH = 1
) (
    input  wire             clk,
    input  wire             rst,
    input  wire [WIDTH-1:0] arm_i,     // DIG_CFG set, DIG_RST, or the power-up arm
    input  wire [WIDTH-1:0] watch_i,   // DIGCFG ENA && IODIR: the latch only watches inputs
    input  wire [WIDTH-1:0] trg_i,     // DIGCFG TRG: 1 fires on 0->1, 0 on 1->0
    input  wire             sample_i,  // POLL_HZ strobe, common to all pins
    input  wire [WIDTH-1:0] level_i,   // synchronized pad levels
    output wire [WIDTH-1:0] fire_o     // one-clock pulses
);
    reg [WIDTH-1:0] armed_q;
    reg [WIDTH-1:0] prev_q;   // meaningful only while armed (an arm loads it)
    reg [WIDTH-1:0] fire_q;

    assign fire_o = fire_q;

    // A sample's clock, as a function called only under sample_i: the edge
    // test (a sample that changes from the previous one to the TRG level)
    // and the fires, {fire, armed}'s next values. A simulator works them out
    // only on a sample's clock (POLL_HZ), where wires would be worked out on
    // every clock; on the others only an arm changes anything. Synthesis
    // sees the same logic functions.
    function [2*WIDTH-1:0] sample_step(input [WIDTH-1:0] arm);
        reg [WIDTH-1:0] hit, fire;
        begin
            // The edge test without the armed bit, which armed's next value
            // takes directly (armed && !fire is armed && !hit): synthesis
            // then gives each of fire and armed a LUT of its own, which
            // nextpnr packs with its flop, rather than feeding fire's LUT
            // into armed's and leaving fire's flop a logic cell alone.
            hit         = watch_i & ~(level_i ^ trg_i) & (prev_q ^ trg_i);
            fire        = armed_q & hit;
            sample_step = {fire & ~arm, arm | (armed_q & ~hit)};
        end
    endfunction

    always @(posedge clk) begin
        if (!sample_i) begin
            // The previous level's load on an arm (see above), as an XOR
            // with the flop, not a mux with the flop as an input, so that
            // synthesis builds no enable (whose LUT would leave the flop a
            // logic cell alone).
            prev_q  <= prev_q ^ ((prev_q ^ level_i) & arm_i);
            fire_q  <= {WIDTH{1'b0}};
            armed_q <= arm_i | armed_q;
        end else begin
            prev_q  <= level_i;
            {fire_q, armed_q} <= sample_step(arm_i);
        end
        if (rst) begin
            armed_q <= {WIDTH{1'b0}};
            fire_q  <= {WIDTH{1'b0}};
            // Only for four-state simulators (Icarus): the arm's XOR load above
            // keeps an unknown previous level unknown, where a mux would load the
            // level, so without it a latch armed before the first sample after
            // power-up missed its first edge there. The flops' synchronous reset
            // input does it, no gate.
            prev_q  <= {WIDTH{1'b0}};
        end
    end

`ifdef FORMAL
`include "bsd_trans_latch_props.vh"
`endif
endmodule
`default_nettype wire
