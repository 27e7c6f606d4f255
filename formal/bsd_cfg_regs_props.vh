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
// f_out_cfg below regroups cfg_o to match.
    reg                  f_past_valid = 1'b0;
    reg                  f_rst_q, f_cfg_we_q, f_out_we_q;
    reg [NUM_PINS-1:0]   f_sel_q;
    reg [5*NUM_PINS-1:0] f_cfg, f_cfg_o_q;
    reg [NUM_PINS-1:0]   f_out, f_out_o_q;
    integer              f_c, f_i, f_k, f_m;
    reg [5*NUM_PINS-1:0] f_out_cfg;   // cfg_o, pin-major
    always @(*)
        for (f_m = 0; f_m < NUM_PINS; f_m = f_m + 1)
            for (f_k = 0; f_k < 5; f_k = f_k + 1)
                f_out_cfg[5*f_m + f_k] = cfg_o[f_k*NUM_PINS + f_m];

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q      <= rst;
        f_cfg_we_q   <= cfg_we_i;
        f_out_we_q   <= out_we_i;
        f_sel_q      <= sel_i;
        f_cfg_o_q    <= f_out_cfg;
        f_out_o_q    <= out_o;
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
        for (f_i = 0; f_i < NUM_PINS; f_i = f_i + 1) begin
            if (FIXED_MASK[f_i]) assert(f_out_cfg[5*f_i +: 5] == FIXED_CFG[8*f_i +: 5]);
            if (f_past_valid) begin
                assert(oe_o[f_i] == !f_out_cfg[5*f_i]);
                assert(watch_o[f_i] == (f_out_cfg[5*f_i + 1] && f_out_cfg[5*f_i]));
                assert(f_out_cfg[5*f_i +: 5] == f_cfg[5*f_i +: 5]);
                assert(out_o[f_i] == f_out[f_i]);
                if (f_rst_q) begin
                    assert(out_o[f_i] == 1'b0);
                    if (!FIXED_MASK[f_i]) assert(f_out_cfg[5*f_i +: 5] == 5'b00001);
                end else begin
                    // Only the addressed pin changes.
                    if (!(f_cfg_we_q && f_sel_q[f_i]))
                        assert(f_out_cfg[5*f_i +: 5] == f_cfg_o_q[5*f_i +: 5]);
                    if (!(f_out_we_q && f_sel_q[f_i]))
                        assert(out_o[f_i] == f_out_o_q[f_i]);
                end
            end
        end
    end

    // Covers: a free pin configured away from its reset value; a fixed pin's output latch
    // set; a configuration write to a fixed pin (it stays); both writes on one clock.
    always @(*) if (f_past_valid && !f_rst_q) begin
        cover(f_out_cfg[4:0] == 5'b10110);
        cover(out_o[1]);
        cover(f_cfg_we_q && f_sel_q == 3'b010 && f_out_cfg[9:5] == FIXED_CFG[12:8]);
        cover(f_cfg_we_q && f_out_we_q && f_sel_q == 3'b100 && f_out_cfg[14:10] != 5'b00001 && out_o[2]);
    end
