// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// The one-shot transition latches (DIGCFG ENA/TRG) of WIDTH pins, bit i
// being pin i's. Arming loads the current level as the previous sample, so
// a level that is already present never fires by itself; an arm on the same
// clock as a matching edge wins (the edge becomes the new baseline). All pins
// are one set of vector operations rather than an instance per pin: a model
// built by Verilator then works on a few words a clock, not on every pin's bits.
// A pin is watched on one bit, ENA && IODIR (bsd_cfg_regs keeps it), and
// the sample is part of the edge test (hit): each of the three flops then
// takes a LUT4 and the previous level's enable a fourth, where the two bits
// took five.
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
    reg [WIDTH-1:0] prev_q;   // meaningful only while armed (an arm loads it): no reset
    reg [WIDTH-1:0] fire_q;

    integer i;

    assign fire_o = fire_q;

    // A sample's clock, as a function called only under sample_i: the edge
    // test (a sample that changes from the previous one to the TRG level),
    // the fires, and the previous levels' loads, {fire, armed, prev}'s next
    // values. A simulator works them out only on a sample's clock (POLL_HZ),
    // where wires would be worked out on every clock; on the others only an
    // arm changes anything. Synthesis sees the same logic functions.
    function [3*WIDTH-1:0] sample_step(input [WIDTH-1:0] arm);
        reg [WIDTH-1:0] watched, hit, fire, load, prev;
        integer b;
        begin
            watched = armed_q & watch_i;
            // The edge test without the armed bit, which armed's next value
            // takes directly (armed && !fire is armed && !hit): synthesis
            // then gives each of fire and armed a LUT of its own, which
            // nextpnr packs with its flop, rather than feeding fire's LUT
            // into armed's and leaving fire's flop a logic cell alone.
            hit     = watch_i & ~(level_i ^ trg_i) & (prev_q ^ trg_i);
            fire    = armed_q & hit;
            load    = arm | watched;
            // (a mux a bit, with the flop as an input: synthesis sees the enable)
            for (b = 0; b < WIDTH; b = b + 1)
                prev[b] = load[b] ? level_i[b] : prev_q[b];
            sample_step = {fire & ~arm, arm | (armed_q & ~hit), prev};
        end
    endfunction

    always @(posedge clk) begin
        if (!sample_i) begin
            // An enable a bit (a flop with an enable, the level its data; the
            // synthesized vector form gives each bit a mux), the loop run only
            // on an arm's clock, where a simulator pays it.
            if (|arm_i) begin
                for (i = 0; i < WIDTH; i = i + 1)
                    if (arm_i[i]) prev_q[i] <= level_i[i];
            end
            fire_q  <= {WIDTH{1'b0}};
            armed_q <= arm_i | armed_q;
        end else begin
            {fire_q, armed_q, prev_q} <= sample_step(arm_i);
        end
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
