// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Per-pin DIGCFG bits 4:0 and output latches. Pins in FIXED_MASK hold
// FIXED_CFG and ignore configuration writes (their output latch stays writable).
// cfg_o is field-major: DIGCFG bit k of pin p is cfg_o[k*NUM_PINS + p], so
// that every consumer takes a field of all pins as one slice (a simulation
// model built by Verilator then works on words, not on every pin's bits).
// The pins are addressed by a one-hot sel_i, decoded once (bsd_parser, with d1): each
// pin's flops then take a shared data bus under an enable of their own (one
// gate a pin, no data mux), and the per-pin loop runs only on a write.
// IODIR is kept inverted only (the output enable, oe_o), and the flops it
// frees keep ENA AND IODIR (watch_o): the transition latch then watches a pin
// on one bit of state rather than two, which saves it a LUT a pin.
// From MEM_PINS (17) pins on, ENA, TSTATE and TMODE (bits 1, 3, 4) are not
// flops but a memory of a word a pin (64 pins: about 200 logic cells fewer;
// on the UP5K an SPRAM with BSD_SPRAM defined, not one of the 30 block RAMs):
// they are read for one command at a time (a DIG_CFG read's reply, a timer's
// start). A read of the pin at addr_i on rd_i's clock (bsd_exec's stage 1)
// shows its bits on every line of those three fields from the clock after
// (stage 2) until the next read (a write does not show before it; after a
// reset they are 0 until then, fixed pins' too); there is no read on a
// write's clock (stage 2 writes; packets are 3 clocks apart). A memory cannot be cleared on reset
// in one clock, so each pin keeps a flag "written since reset", and a pin
// without it reads its reset (or FIXED) value.
module bsd_cfg_regs #(
    parameter integer               NUM_PINS   = 5,
    parameter [NUM_PINS-1:0]        FIXED_MASK = 0,
    parameter [8*NUM_PINS-1:0]      FIXED_CFG  = 0,
    // From this many pins on, ENA, TSTATE and TMODE are a memory (see above).
    // Below, it saves a few LUTs and would move GP 1.0's paths and its
    // simulation (docs/synthesis.md). The proofs set it to check both forms.
    parameter integer               MEM_PINS   = 17
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  cfg_we_i,
    input  wire                  out_we_i,
    input  wire [NUM_PINS-1:0]   sel_i,        // the pin the writes and a read address (one-hot or none)
    input  wire [5:0]            addr_i,       // the pin a read (and, with the memory, a
                                               // configuration write) addresses: sel_i's line
    input  wire                  rd_i,         // read the pin (used only with the memory)
    input  wire [4:0]            cfg_wdata_i,
    input  wire                  out_wdata_i,
    output wire [5*NUM_PINS-1:0] cfg_o,        // every pin's DIGCFG bits 4:0, field-major
    output wire [NUM_PINS-1:0]   out_o,        // every pin's output latch
    output wire [NUM_PINS-1:0]   oe_o,         // every pin's output enable: !IODIR
    output wire [NUM_PINS-1:0]   watch_o       // every pin's ENA && IODIR: its latch watches it
);
    // Input, latch disarmed. With the memory its bits 4:3 and 1 must stay 0: a
    // pin whose word is not written since reset reads 0 there.
    localparam [4:0] CFG_RESET = 5'b00001;
    localparam [0:0] MEM = NUM_PINS >= MEM_PINS;

    // FIXED_CFG's bits 4:0, field-major like cfg_o. Called only for a
    // localparam (evaluated at elaboration): outside coverage.
    /* verilator coverage_off */
    function [5*NUM_PINS-1:0] fixed_fields(input integer unused);
        integer k, q;
        begin
            for (k = 0; k < 5; k = k + 1)
                for (q = 0; q < NUM_PINS; q = q + 1)
                    fixed_fields[k*NUM_PINS + q] = FIXED_CFG[8*q + k];
        end
    endfunction
    /* verilator coverage_on */
    localparam [5*NUM_PINS-1:0] FIXED_F = fixed_fields(0);

    // Field-major, DIGCFG bits 4:1 (bit 0, IODIR, is oe_q's inverse); a
    // fixed pin's bits are never read.
    reg [5*NUM_PINS-1:NUM_PINS] cfg_q;
    reg [NUM_PINS-1:0]   out_q;
    // The output enable is IODIR inverted, so that the pad's enable needs no
    // gate per pin; the readers of IODIR invert it inside their own gates.
    reg [NUM_PINS-1:0]   oe_q;
    reg [NUM_PINS-1:0]   watch_q;
    wire [2:0]           rd_bits;   // with the memory: the read pin's TMODE, TSTATE, ENA
    integer k, p;

    always @(posedge clk) begin
        // Written as per-pin enables over a shared data bus, so that synthesis
        // builds clock-enabled flops rather than a data mux per bit.
        if (cfg_we_i) begin
            for (p = 0; p < NUM_PINS; p = p + 1) begin
                if (sel_i[p]) begin
                    for (k = 1; k < 5; k = k + 1)
                        cfg_q[k*NUM_PINS + p] <= cfg_wdata_i[k];
                    oe_q[p]    <= !cfg_wdata_i[0];
                    watch_q[p] <= cfg_wdata_i[1] && cfg_wdata_i[0];
                end
            end
        end
        // The output latches: the write's strobe as the enable all pins
        // share, and the select an AND-OR in each bit's data, so that each
        // flop takes a LUT of its own (select, data, itself) that nextpnr
        // packs with it. A per-pin enable (strobe AND select) took a LUT a
        // pin and left the flop a logic cell alone (64 pins: 64 cells more).
        if (out_we_i)
            out_q <= (out_q & ~sel_i) | (sel_i & {NUM_PINS{out_wdata_i}});
        if (rst) begin
            for (k = 1; k < 5; k = k + 1)
                cfg_q[k*NUM_PINS +: NUM_PINS] <= {NUM_PINS{CFG_RESET[k]}};
            oe_q    <= {NUM_PINS{!CFG_RESET[0]}};
            watch_q <= {NUM_PINS{CFG_RESET[1] && CFG_RESET[0]}};
            out_q <= {NUM_PINS{1'b0}};
        end
    end

    assign cfg_o[0 +: NUM_PINS] = (~oe_q & ~FIXED_MASK) | (FIXED_F[0 +: NUM_PINS] & FIXED_MASK);
    genvar g;
    generate
        for (g = 1; g < 5; g = g + 1) begin : g_field
            if (!MEM || g == 2) begin : g_flops
                assign cfg_o[g*NUM_PINS +: NUM_PINS] = (cfg_q[g*NUM_PINS +: NUM_PINS] & ~FIXED_MASK) |
                                                       (FIXED_F[g*NUM_PINS +: NUM_PINS] & FIXED_MASK);
            end else begin : g_read
                // The read pin's bit on every line (its flops are never read).
                assign cfg_o[g*NUM_PINS +: NUM_PINS] = {NUM_PINS{rd_bits[g == 1 ? 0 : g - 2]}};
                wire unused_field = ^cfg_q[g*NUM_PINS +: NUM_PINS];
            end
        end
        if (MEM) begin : g_mem
            // A word a pin, 64 whatever NUM_PINS is: an address past the last
            // pin (never read with its flag) aliases no pin. Outside coverage,
            // as the toggle count takes an array's bits below 256 of them,
            // words of no pin included; its data is counted at cfg_o.
            /* verilator coverage_off */
`ifdef BSD_SPRAM
            (* ram_style = "huge" *)
`endif
            reg [2:0]          mem [0:63];
            /* verilator coverage_on */
            reg [2:0]          mem_rd_q;
            reg [NUM_PINS-1:0] wr_q;      // the pin's word is written since reset
            reg                wr_rd_q;   // the read pin's flag
            reg [2:0]          fix_rd_q;  // the read pin's FIXED bits 4, 3, 1 (zero for a free pin)
            integer            q;
            always @(posedge clk) begin
                if (cfg_we_i) begin
                    for (q = 0; q < NUM_PINS; q = q + 1)
                        if (sel_i[q]) wr_q[q] <= 1'b1;
                end
                if (rd_i && !cfg_we_i) begin
                    wr_rd_q  <= |(wr_q & ~FIXED_MASK & sel_i);
                    fix_rd_q <= {|(FIXED_F[4*NUM_PINS +: NUM_PINS] & FIXED_MASK & sel_i),
                                 |(FIXED_F[3*NUM_PINS +: NUM_PINS] & FIXED_MASK & sel_i),
                                 |(FIXED_F[1*NUM_PINS +: NUM_PINS] & FIXED_MASK & sel_i)};
                end
                if (rst) begin
                    wr_q     <= {NUM_PINS{1'b0}};   // ENA, TSTATE and TMODE read as CFG_RESET's: 0
                    wr_rd_q  <= 1'b0;               // (and no unknown word before a first read)
                    fix_rd_q <= 3'd0;
                end
            end
            // The memory's ports apart from reset (a block or single-port RAM has none).
            always @(posedge clk) begin
                if (cfg_we_i)
                    mem[addr_i] <= {cfg_wdata_i[4:3], cfg_wdata_i[1]};
                else if (rd_i)
                    mem_rd_q <= mem[addr_i];
            end
            // Kept as one net: synthesis would otherwise fold the flag's AND into
            // each timer's start logic (TMODE and TSTATE go to every timer).
            (* keep *) wire [2:0] rd_w = (mem_rd_q & {3{wr_rd_q}}) | fix_rd_q;
            assign rd_bits = rd_w;
        end else begin : g_no_mem
            assign rd_bits = 3'd0;
            wire unused_rd = ^{addr_i, rd_i, rd_bits};
        end
    endgenerate
    assign out_o = out_q;
    assign oe_o  = (oe_q & ~FIXED_MASK) | (~FIXED_F[0 +: NUM_PINS] & FIXED_MASK);
    assign watch_o = (watch_q & ~FIXED_MASK) |
                     (FIXED_F[1*NUM_PINS +: NUM_PINS] & FIXED_F[0 +: NUM_PINS] & FIXED_MASK);

`ifdef FORMAL
`include "bsd_cfg_regs_props.vh"
`endif
endmodule
`default_nettype wire
