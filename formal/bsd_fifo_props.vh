// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_fifo (included at the end of the module under `ifdef FORMAL).
// The source obeys AXI-Stream and sends 0, 1, 2, ... (mod 2^WIDTH) (assumed: data
// independence); the output must obey AXI-Stream and carry the same sequence (no word lost,
// duplicated or reordered). Full and empty are exact, and the RAM is never read and
// written at one address on one clock.
    reg             f_past_valid = 1'b0;
    reg             f_rst_q, f_sv_q, f_sr_q, f_mv_q, f_mr_q;
    reg [WIDTH-1:0] f_sd_q, f_md_q;
    reg [WIDTH-1:0] f_in_cnt, f_out_cnt;
    wire [WIDTH-1:0] f_held = f_in_cnt - f_out_cnt;
    // The pointers step through the addresses in the LFSR's order: their positions in that
    // order (f_wr_n, f_rd_n, counted by + 1 beside them) are what the occupancy is made of.
    reg [AW-1:0]     f_wr_n, f_rd_n;
    // The address k steps after a.
    function [AW-1:0] f_after(input [AW-1:0] a, input integer k);
        integer f_s;
        begin
            f_after = a;
            for (f_s = 0; f_s < DEPTH; f_s = f_s + 1)
                if (f_s < k) f_after = step(f_after);
        end
    endfunction
    // The RAM's words: the pointers' distance, or DEPTH when full (equal pointers either way).
    wire [AW:0]      f_ram  = ram_full_q ? DEPTH[AW:0] : {1'b0, f_wr_n - f_rd_n};

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata;
        if (s_axis_tvalid && s_axis_tready) f_in_cnt  <= f_in_cnt + 1'b1;
        if (m_axis_tvalid && m_axis_tready) f_out_cnt <= f_out_cnt + 1'b1;
        if (push) f_wr_n <= f_wr_n + 1'b1;
        if (pop)  f_rd_n <= f_rd_n + 1'b1;
        if (rst) begin
            f_in_cnt  <= {WIDTH{1'b0}};
            f_out_cnt <= {WIDTH{1'b0}};
            f_wr_n    <= {AW{1'b0}};
            f_rd_n    <= {AW{1'b0}};
        end
    end

    integer f_k;
    reg [WIDTH-1:0] f_exp;
    always @(*) begin
        f_k = 0;
        f_exp = {WIDTH{1'b0}};
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && f_sv_q && !f_sr_q) begin
            assume(s_axis_tvalid);
            assume(s_axis_tdata == f_sd_q);
        end
        if (s_axis_tvalid) assume(s_axis_tdata == f_in_cnt);
        if (f_past_valid && !f_rst_q) begin
            if (f_mv_q && !f_mr_q) begin
                assert(m_axis_tvalid);
                assert(m_axis_tdata == f_md_q);
            end
            if (m_axis_tvalid) assert(m_axis_tdata == f_out_cnt);
            // Occupancy: the RAM's words plus the read register's and the skid's.
            assert(f_ram <= DEPTH);
            assert(!skid_valid || out_valid_q);
            assert(f_held == f_ram + {{(WIDTH-1){1'b0}}, out_valid_q} + {{(WIDTH-1){1'b0}}, skid_valid});
            // The skid holds the head, the read register the word after it.
            if (skid_valid) begin
                assert(skid_data_q == f_out_cnt);
                assert(out_data_q == f_out_cnt + 1'b1);
            end else if (out_valid_q) begin
                assert(out_data_q == f_out_cnt);
            end
            // Full and empty exact.
            assert(ram_empty_q == (f_ram == 0));
            assert(ram_full_q == (f_ram == DEPTH));
            assert(!(ram_full_q && ram_empty_q));
            if (ram_full_q) assert(wr_q == rd_q);
            // Each pointer is the address its position names (from 0 at reset), and the
            // LFSR's order visits every address before it repeats.
            assert(wr_q == f_after({AW{1'b0}}, f_wr_n));
            assert(rd_q == f_after({AW{1'b0}}, f_rd_n));
            assert(f_after({AW{1'b0}}, DEPTH) == {AW{1'b0}});
            for (f_k = 1; f_k < DEPTH; f_k = f_k + 1)
                assert(f_after({AW{1'b0}}, f_k) != {AW{1'b0}});
            assert(s_axis_tready == (f_ram != DEPTH));
            assert(empty_o == (f_held == 0));
            // Never a read and a write of one RAM address on one clock.
            assert(!(push && pop && wr_q == rd_q));
            // Induction: the RAM holds the next words in order.
            for (f_k = 0; f_k < DEPTH; f_k = f_k + 1)
                if (f_k < f_ram) begin
                    f_exp = f_out_cnt + out_valid_q + skid_valid + f_k;
                    assert(mem[f_after(rd_q, f_k)] == f_exp);
                end
        end
    end

    reg f_was_full = 1'b0;
    always @(posedge clk) if (ram_full_q) f_was_full <= 1'b1;
    always @(*) if (f_past_valid && !rst) begin
        cover(ram_full_q && (skid_valid || SKID == 0)); // DEPTH + SKID + 1 words held
        cover(f_was_full && empty_o);                // filled, then drained
        cover(push && pop);                          // a write and a read on one clock
    end
