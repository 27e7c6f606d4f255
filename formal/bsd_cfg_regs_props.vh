// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_cfg_regs (included at the end of the module under `ifdef FORMAL).
// Inputs free (reset on the first clock). A reference register file written from the
// header and PROTOCOL.md §3/§6: after reset every free pin's DIGCFG bits are 0x01 and every
// output latch 0; a configuration write stores cfg_wdata_i in the free pins sel_i selects
// only (any sel_i, one-hot or not); an output write stores out_wdata_i in the selected
// pins' latches only (fixed pins too). A fixed pin's cfg_o is FIXED_CFG's bits 4:0 on
// every clock, reset included. cfg_o and out_o (the read-back) equal the reference after
// every clock, and on a write every other pin keeps its value. oe_o is IODIR (bit 0) inverted
// and watch_o is ENA (bit 1) AND IODIR on every clock. cfg_o is field-major (bit k of pin p
// at k*NUM_PINS + p); the reference keeps pin-major words (pin p's bits at 5*p) and
// f_out_cfg below regroups cfg_o to match. With the memory, a read shows the pin's bits 4, 3
// and 1 on every line of cfg_o and its bits 4:1 on rd_cfg_o from the clock after (0 after
// reset until then); rd_cfg_o is 0 without the memory.
    reg                  f_past_valid = 1'b0;
    reg                  f_rst_q, f_cfg_we_q, f_out_we_q;
    reg [NUM_PINS-1:0]   f_sel_q;
    reg [5*NUM_PINS-1:0] f_cfg, f_cfg_o_q;
    reg [NUM_PINS-1:0]   f_out, f_out_o_q;
    integer              f_c, f_i, f_k, f_m;
    reg [5*NUM_PINS-1:0] f_out_cfg;   // cfg_o, pin-major
    reg [3:0]            f_rd;        // with the memory: the last read pin's bits 4:1
    reg [5*NUM_PINS-1:0] f_shown;     // what cfg_o shows, pin-major
    always @(*)
        for (f_m = 0; f_m < NUM_PINS; f_m = f_m + 1) begin
            for (f_k = 0; f_k < 5; f_k = f_k + 1)
                f_out_cfg[5*f_m + f_k] = cfg_o[f_k*NUM_PINS + f_m];
            f_shown[5*f_m +: 5] = MEM ? {f_rd[3:2], f_cfg[5*f_m + 2], f_rd[0], f_cfg[5*f_m]}
                                      : f_cfg[5*f_m +: 5];
        end

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q      <= rst;
        f_cfg_we_q   <= cfg_we_i;
        f_out_we_q   <= out_we_i;
        f_sel_q      <= sel_i;
        f_cfg_o_q    <= f_out_cfg;
        f_out_o_q    <= out_o;
        if (rd_i && !rst)
            f_rd <= addr_i < NUM_PINS ? f_cfg[5*addr_i + 1 +: 4] : 4'd0;
        if (rst) f_rd <= 4'd0;
        for (f_c = 0; f_c < NUM_PINS; f_c = f_c + 1) begin
            if (cfg_we_i && sel_i[f_c] && !FIXED_MASK[f_c]) f_cfg[5*f_c +: 5] <= cfg_wdata_i;
            if (out_we_i && sel_i[f_c]) f_out[f_c] <= out_wdata_i;
            if (rst) begin
                f_cfg[5*f_c +: 5] <= FIXED_MASK[f_c] ? FIXED_CFG[8*f_c +: 5] : 5'b00001;
                f_out[f_c]        <= 1'b0;
            end
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        // With the memory, as bsd_exec and bsd_parser drive it: sel_i is addr_i's line (none
        // past the last pin), there is no read on a write's clock, and neither while the
        // memory is swept after reset (the core's parser holds packets while busy_o).
        if (MEM) begin
            assume(sel_i == (addr_i < NUM_PINS ? {{(NUM_PINS-1){1'b0}}, 1'b1} << addr_i : {NUM_PINS{1'b0}}));
            assume(!(rd_i && cfg_we_i));
            if (busy_o && !rst) assume(!rd_i && !cfg_we_i);
        end else begin
            assert(!busy_o);
        end
        if (f_past_valid) assert(rd_cfg_o == (MEM ? f_rd : 4'd0));
        for (f_i = 0; f_i < NUM_PINS; f_i = f_i + 1) begin
            if (FIXED_MASK[f_i] && !MEM) assert(f_out_cfg[5*f_i +: 5] == FIXED_CFG[8*f_i +: 5]);
            if (f_past_valid) begin
                if (FIXED_MASK[f_i]) assert(f_cfg[5*f_i +: 5] == FIXED_CFG[8*f_i +: 5]);
                assert(oe_o[f_i] == !f_cfg[5*f_i]);
                assert(watch_o[f_i] == (f_cfg[5*f_i + 1] && f_cfg[5*f_i]));
                assert(f_out_cfg[5*f_i +: 5] == f_shown[5*f_i +: 5]);
                assert(out_o[f_i] == f_out[f_i]);
                if (f_rst_q) begin
                    assert(out_o[f_i] == 1'b0);
                    if (!FIXED_MASK[f_i]) assert(f_out_cfg[5*f_i +: 5] == 5'b00001);
                end else begin
                    // Only the addressed pin changes (with the memory, bits 4, 3 and 1
                    // show the read pin's: the reference above).
                    if (!(f_cfg_we_q && f_sel_q[f_i]) && !MEM)
                        assert(f_out_cfg[5*f_i +: 5] == f_cfg_o_q[5*f_i +: 5]);
                    if (!(f_out_we_q && f_sel_q[f_i]))
                        assert(out_o[f_i] == f_out_o_q[f_i]);
                end
            end
        end
    end

    // For induction, with the memory: a pin's word is its bits 4:1 once the sweep
    // after reset has passed it (always outside the sweep), and the sweep stops at the
    // last pin.
    generate
        if (MEM) begin : g_f_mem
            integer f_w;
            always @(*)
                if (f_past_valid) begin
                    if (g_mem.clr_q) assert(g_mem.clr_pin_q < NUM_PINS);
                    for (f_w = 0; f_w < NUM_PINS; f_w = f_w + 1)
                        if (!g_mem.clr_q || f_w < g_mem.clr_pin_q)
                            assert(g_mem.mem[f_w] == f_cfg[5*f_w + 1 +: 4]);
                end
        end
    endgenerate

    // Covers: a free pin configured away from its reset value; a fixed pin's output latch
    // set; a configuration write to a fixed pin (it stays); both writes on one clock; a pin
    // written, reset and read (the sweep has cleared its word: 0x01).
    reg f_dirty0, f_wr_rst;
    always @(posedge clk) begin
        if (cfg_we_i && sel_i[0]) begin
            f_dirty0 <= cfg_wdata_i[4:1] != 4'd0;
            f_wr_rst <= 1'b0;
        end
        if (rst) begin
            f_dirty0 <= 1'b0;
            f_wr_rst <= f_past_valid && (f_dirty0 || f_wr_rst);
        end
    end
    reg f_rd0_q;   // a read of pin 0 on the previous clock
    always @(posedge clk) f_rd0_q <= rd_i && !rst && addr_i == 6'd0;
    always @(*) if (f_past_valid && !f_rst_q)
        cover(f_wr_rst && f_rd0_q && f_out_cfg[4:0] == 5'b00001);
    always @(*) if (f_past_valid && !f_rst_q) begin
        cover(f_out_cfg[4:0] == 5'b10110);
        cover(out_o[1]);
        cover(f_cfg_we_q && f_sel_q == 3'b010 && f_out_cfg[9:5] == FIXED_CFG[12:8]);
        cover(f_cfg_we_q && f_out_we_q && f_sel_q == 3'b100 && f_out_cfg[14:10] != 5'b00001 && out_o[2]);
    end
