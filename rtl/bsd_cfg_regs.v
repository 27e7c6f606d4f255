// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Per-pin DIGCFG bits 4:0 and output latches. Pins in FIXED_MASK hold
// FIXED_CFG and ignore configuration writes (their output latch stays writable).
// cfg_o is field-major: DIGCFG bit k of pin p is cfg_o[k*NUM_PINS + p], so
// that every consumer takes a field of all pins as one slice (a simulation
// model built by Verilator then works on words, not on every pin's bits).
// The pins are addressed by a one-hot sel_i, decoded once (bsd_parser, with d1; from
// MEM_PINS bsd_exec): each pin's flops then take a shared data bus under an enable of
// their own (one gate a pin, no data mux), and the per-pin loop runs only on a write;
// from MEM_PINS on, the three flops a pin keeps take the select in their data instead
// (g_mem, below).
// IODIR is kept inverted only (the output enable, oe_o), and the flops it
// frees keep ENA AND IODIR (watch_o): the transition latch then watches a pin
// on one bit of state rather than two, which saves it a LUT a pin.
// From MEM_PINS (17) pins on, ENA, TSTATE and TMODE (bits 1, 3, 4) are not
// flops but a memory of a word a pin (64 pins: about 270 logic cells fewer;
// on the UP5K an SPRAM with BSD_SPRAM defined, not one of the 30 block RAMs):
// they are read for one command at a time (a DIG_CFG read's reply, a timer's
// start). A read of the pin at addr_i on rd_i's clock (bsd_exec's stage 1)
// shows its bits on every line of those three fields from the clock after
// (stage 2) until the next read (a write does not show before it; after a
// reset they are 0 until then, fixed pins' too); there is no read on a
// write's clock (stage 2 writes; packets are 3 clocks apart). The word keeps
// TRG as well, which the pin's transition latch reads from a flop, so that
// the read shows all of bits 4:1 on rd_cfg_o for a DIG_CFG read's reply. A memory cannot
// be cleared in one clock, so after reset the block writes every pin's word
// with its reset (or FIXED) bits, a pin a clock, and says so on busy_o; the
// core's parser holds packets meanwhile (NUM_PINS clocks, 64 at most: a
// sixteenth of a byte's time at 115200 baud and 12 MHz), so no read or write
// meets the sweep. A flag a pin "written since reset" did the same without
// the wait, and cost 64 pins about 90 logic cells more (the flags, and the OR
// over them that a read needs).
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
    output wire [NUM_PINS-1:0]   watch_o,      // every pin's ENA && IODIR: its latch watches it
    // With the memory, the read pin's DIGCFG bits 4:1 (as the fields of cfg_o that
    // the memory keeps show them, and its TRG, which a flop a pin keeps as well
    // for its transition latch: bsd_exec's DIG_CFG read then needs no lookup
    // over the pins); 0 without it.
    output wire [3:0]            rd_cfg_o,
    output wire                  busy_o        // the memory is being cleared: no rd_i or cfg_we_i
);
    // Input, latch disarmed.
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

    // With the memory: every pin's word after reset, DIGCFG bits 4:1, FIXED_CFG's
    // for a fixed pin and CFG_RESET's for a free one. Called only for a localparam.
    /* verilator coverage_off */
    function [255:0] reset_words(input integer unused);
        integer r;
        begin
            reset_words = 256'd0;
            // (64 words: a NUM_PINS above 64 is the top's parameter check's to reject)
            for (r = 0; r < NUM_PINS && r < 64; r = r + 1)
                reset_words[4*r +: 4] = FIXED_MASK[r] ? FIXED_CFG[8*r + 1 +: 4] : CFG_RESET[4:1];
        end
    endfunction
    /* verilator coverage_on */
    localparam [255:0] RESET_WORDS = reset_words(0);

    // Field-major, DIGCFG bits 4:1 (bit 0, IODIR, is oe_q's inverse); a
    // fixed pin's bits are never read.
    reg [5*NUM_PINS-1:NUM_PINS] cfg_q;
    reg [NUM_PINS-1:0]   out_q;
    // The output enable is IODIR inverted, so that the pad's enable needs no
    // gate per pin; the readers of IODIR invert it inside their own gates.
    reg [NUM_PINS-1:0]   oe_q;
    reg [NUM_PINS-1:0]   watch_q;
    wire [3:0]           rd_bits;   // with the memory: the read pin's DIGCFG bits 4:1
    // The flops the outputs read: TRG, oe and watch (g_mem has its own).
    wire [NUM_PINS-1:0]  trg_w, oe_w, watch_w;
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

    assign cfg_o[0 +: NUM_PINS] = (~oe_w & ~FIXED_MASK) | (FIXED_F[0 +: NUM_PINS] & FIXED_MASK);
    genvar g;
    generate
        for (g = 1; g < 5; g = g + 1) begin : g_field
            if (!MEM || g == 2) begin : g_flops
                assign cfg_o[g*NUM_PINS +: NUM_PINS] = ((g == 2 ? trg_w : cfg_q[g*NUM_PINS +: NUM_PINS]) & ~FIXED_MASK) |
                                                       (FIXED_F[g*NUM_PINS +: NUM_PINS] & FIXED_MASK);
            end else begin : g_read
                // The read pin's bit on every line (its flops are never read).
                assign cfg_o[g*NUM_PINS +: NUM_PINS] = {NUM_PINS{rd_bits[g - 1]}};
                wire unused_field = ^cfg_q[g*NUM_PINS +: NUM_PINS];
            end
        end
        if (MEM) begin : g_mem
            // A word a pin, 64 whatever NUM_PINS is (the sweep writes only the
            // pins'; a read past the last pin shows 0, rd_ok_q). Outside coverage,
            // as the toggle count takes an array's bits below 256 of them,
            // words of no pin included; its data is counted at cfg_o.
            /* verilator coverage_off */
`ifdef BSD_SPRAM
            (* ram_style = "huge" *)
`endif
            reg [3:0]          mem [0:63];
            /* verilator coverage_on */
            reg [3:0]          mem_rd_q;
            reg                rd_ok_q;   // the last read since reset was of a pin
            reg                clr_q;     // the sweep after reset
            reg [5:0]          clr_pin_q; // the pin it writes
            localparam [5:0]   LAST_PIN    = NUM_PINS[5:0] - 6'd1;
            localparam [63:0]  PIN_ADDR    = {64{1'b1}} >> (64 - NUM_PINS);  // the addresses of pins
            always @(posedge clk) begin
                if (rd_i && !cfg_we_i) rd_ok_q <= PIN_ADDR[addr_i];
                if (clr_q) begin
                    clr_pin_q <= clr_pin_q + 6'd1;
                    if (clr_pin_q == LAST_PIN) clr_q <= 1'b0;
                end
                if (rst) begin
                    rd_ok_q   <= 1'b0;   // the fields read 0 until the first read
                    clr_q     <= 1'b1;
                    clr_pin_q <= 6'd0;
                end
            end
            // The memory's one port, apart from reset (a block or single-port
            // RAM has none), with one address (an SPRAM has one): the sweep, else
            // a write (a fixed pin's word is FIXED_CFG's for good: writes pass it
            // by, as its flops above), else a read.
            wire [5:0] mem_addr = clr_q ? clr_pin_q : addr_i;
            always @(posedge clk) begin
                if (clr_q) begin
                    mem[mem_addr] <= RESET_WORDS[4*clr_pin_q +: 4];
                end else if (cfg_we_i) begin
                    if (!(|(sel_i & FIXED_MASK))) mem[mem_addr] <= cfg_wdata_i[4:1];
                end else if (rd_i) begin
                    mem_rd_q <= mem[mem_addr];
                end
            end
`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the props assume it
            // The core's promise (its parser holds packets while busy_o), checked
            // in every simulation: a read or write would meet the sweep. A check
            // that fires only on a design error: outside coverage.
            /* verilator coverage_off */
            always @(posedge clk) begin
                if (clr_q) begin
                    if (!rst && (rd_i || cfg_we_i))
                        $fatal(1, "bsd_cfg_regs: a read or write while the memory is cleared");
                end
            end
            /* verilator coverage_on */
`endif
`endif
            // A pin's three flops that anything reads (TRG, oe, watch), with
            // the memory: written as the output latches are (below), the
            // strobe the enable all pins share and the select in each bit's
            // data, so that each takes a LUT of its own that nextpnr packs
            // with it. The shared block's per-pin enable took a LUT a pin and
            // left each of the three a logic cell alone (uart64t: 43 cells
            // fewer). Below MEM_PINS a pin's six flops share that LUT and this
            // form is the larger (core5 693 -> 715 LUT4), so the small builds
            // keep the shared block's flops, which nothing reads from here on.
            reg [NUM_PINS-1:0] trg_q, oe_m_q, watch_m_q;
            always @(posedge clk) begin
                if (cfg_we_i) begin
                    trg_q     <= (trg_q & ~sel_i) | (sel_i & {NUM_PINS{cfg_wdata_i[2]}});
                    oe_m_q    <= (oe_m_q & ~sel_i) | (sel_i & {NUM_PINS{!cfg_wdata_i[0]}});
                    watch_m_q <= (watch_m_q & ~sel_i) | (sel_i & {NUM_PINS{cfg_wdata_i[1] && cfg_wdata_i[0]}});
                end
                if (rst) begin
                    trg_q     <= {NUM_PINS{CFG_RESET[2]}};
                    oe_m_q    <= {NUM_PINS{!CFG_RESET[0]}};
                    watch_m_q <= {NUM_PINS{CFG_RESET[1] && CFG_RESET[0]}};
                end
            end
            assign trg_w   = trg_q;
            assign oe_w    = oe_m_q;
            assign watch_w = watch_m_q;
            wire unused_flops = ^{cfg_q[2*NUM_PINS +: NUM_PINS], oe_q, watch_q};
            // Kept as one net: synthesis would otherwise fold the AND into
            // each timer's start logic (TMODE and TSTATE go to every timer).
            (* keep *) wire [3:0] rd_w = mem_rd_q & {4{rd_ok_q}};
            assign rd_bits = rd_w;
            assign busy_o  = clr_q;
        end else begin : g_no_mem
            assign rd_bits = 4'd0;
            assign busy_o  = 1'b0;
            assign trg_w   = cfg_q[2*NUM_PINS +: NUM_PINS];
            assign oe_w    = oe_q;
            assign watch_w = watch_q;
            wire unused_rd = ^{addr_i, rd_i};
        end
    endgenerate
    assign out_o = out_q;
    assign rd_cfg_o = rd_bits;
    assign oe_o  = (oe_w & ~FIXED_MASK) | (~FIXED_F[0 +: NUM_PINS] & FIXED_MASK);
    assign watch_o = (watch_w & ~FIXED_MASK) |
                     (FIXED_F[1*NUM_PINS +: NUM_PINS] & FIXED_F[0 +: NUM_PINS] & FIXED_MASK);

`ifdef FORMAL
`include "bsd_cfg_regs_props.vh"
`endif
endmodule
`default_nettype wire
