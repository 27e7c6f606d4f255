// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_axis_skid (included at the end of the module under `ifdef FORMAL).
// The input obeys AXI-Stream (assumed); the output must (asserted). Data independence: the
// source sends the numbers 0, 1, 2, ... (mod 2^WIDTH), so the output must carry the same
// sequence: no word lost, duplicated or reordered. s_axis_tready is exact: 0 only when two
// words are held.
    reg             f_past_valid = 1'b0;
    reg             f_rst_q, f_sv_q, f_sr_q, f_mv_q, f_mr_q;
    reg [WIDTH-1:0] f_sd_q, f_md_q;
    reg [WIDTH-1:0] f_in_cnt, f_out_cnt;
    wire [WIDTH-1:0] f_held = f_in_cnt - f_out_cnt;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata;
        if (s_axis_tvalid && s_axis_tready) f_in_cnt  <= f_in_cnt + 1'b1;
        if (m_axis_tvalid && m_axis_tready) f_out_cnt <= f_out_cnt + 1'b1;
        if (rst) begin
            f_in_cnt  <= {WIDTH{1'b0}};
            f_out_cnt <= {WIDTH{1'b0}};
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        // The source: AXI-Stream, and the counting sequence.
        if (f_past_valid && !f_rst_q && f_sv_q && !f_sr_q) begin
            assume(s_axis_tvalid);
            assume(s_axis_tdata == f_sd_q);
        end
        if (s_axis_tvalid) assume(s_axis_tdata == f_in_cnt);
        if (f_past_valid && !f_rst_q) begin
            // The sink sees AXI-Stream: a stalled word stays, unchanged.
            if (f_mv_q && !f_mr_q) begin
                assert(m_axis_tvalid);
                assert(m_axis_tdata == f_md_q);
            end
            // Order: the next word out is the next number.
            if (m_axis_tvalid) assert(m_axis_tdata == f_out_cnt);
            // Exactly the words accepted and not yet delivered are held.
            assert(f_held == {{(WIDTH-1){1'b0}}, out_valid_q} + {{(WIDTH-1){1'b0}}, skid_valid_q});
            assert(s_axis_tready == (f_held < 2));
            // Internal invariant for induction: the skid holds the word after the output's.
            if (skid_valid_q) begin
                assert(out_valid_q);
                assert(skid_q == f_out_cnt + 1'b1);
            end
        end
    end

    // Cover: full, then back to empty having passed 4 words.
    reg f_was_full = 1'b0;
    always @(posedge clk) if (skid_valid_q) f_was_full <= 1'b1;
    always @(*) if (f_past_valid && !rst) begin
        cover(skid_valid_q);
        cover(f_was_full && !out_valid_q && f_out_cnt == 4);
    end
