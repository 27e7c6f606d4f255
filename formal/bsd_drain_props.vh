// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_drain (included at the end of the module under `ifdef FORMAL).
// The event queue's head is assumed to obey AXI-Stream (an entry offered stays offered,
// unchanged, until taken); entries (with timer events or not: ev_timers_i, which promises
// r and f valid and not both zero), delivery flags and DIG_IO values are free.
// Asserted, the order of one entry (PROTOCOL.md §5, DESIGN.md decisions 1 and 9): one item
// a clock; timers in ascending order; the DIG_IO value before the first timer whose ID is
// above its own and after every timer whose ID is not; the reply after every timer and the
// DIG_IO value, the heartbeat last; every item of an entry taken exactly once before the
// next entry is loaded (nothing lost or repeated), and the next one loaded on the clock after
// the last item goes (an item every clock, and one idle clock between entries), or in the
// memory form (from MEM_TIMERS) a clock later after an entry with timer events: stage A
// reads its r, f and T from the queue's head, so it is taken from the queue only on that
// idle clock; there, an entry whose last item is a timer has one idle clock more before
// "no item left" (the clock after that item finds no timer left). With consecutive timer IDs
// there (RANK_IDX: the prove_memc task) the value is ranked at stage A, not in the pick: it
// reaches stage B before the first timer whose ID is above its own and after every other,
// by a hold of one clock, which counts as its take. Asserted for both forms: each entry offered is loaded once and taken once,
// after or as it loads, and stage A's r, f and T are its entry's (a copy made here).
    reg                f_past_valid = 1'b0;
    reg                f_rst_q, f_v_q, f_r_q, f_t_q;
    reg [2*NT+25:0]    f_d_q;
    reg [3:0]          f_items, f_taken;
    reg                f_have_k, f_dio_done;
    reg [5:0]          f_last_k;
    reg                f_loaded;           // the head's entry was loaded and is not yet taken
    reg [2*NT+25:0]    f_e_q;              // the entry loaded last
    integer            f_j2;
    wire [5:0]         k_id = CONTIG ? ID0 + k : IDS[6*k +: 6];  // the picked timer's ID

    function [3:0] f_count(input [2*NT+25:0] e, input tv);
        integer f_j;
        begin
            f_count = {3'd0, e[25]} + {3'd0, e[24]} + {3'd0, e[23]};
            for (f_j = 0; f_j < NT; f_j = f_j + 1)
                f_count = f_count + {3'd0, tv & (e[26 + f_j] | e[26 + NT + f_j])};
        end
    endfunction

    // The items left: the entry's flops' (for induction: each taken item is counted once).
    function [3:0] f_left(input [NT-1:0] v);
        integer f_j;
        begin
            f_left = {3'd0, dio_q} + {3'd0, rep_q} + {3'd0, hb_q};
            for (f_j = 0; f_j < NT; f_j = f_j + 1)
                f_left = f_left + {3'd0, v[f_j]};
        end
    endfunction

    // (a hold takes the DIG_IO value, and no step runs: step()'s takes are not taken)
    wire [2:0] f_takes = hold ? 3'd1 : {2'd0, take_t} + {2'd0, take_dio} + {2'd0, take_rep} + {2'd0, take_hb};
    wire [5:0] f_a_id  = CONTIG ? ID0 + a_k_q : IDS[6*a_k_q +: 6];  // stage A's timer's ID

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_v_q   <= ev_valid_i;
        f_r_q   <= ev_ready_o;
        f_d_q   <= ev_data_i;
        f_t_q   <= ev_timers_i;
        f_taken <= f_taken + {1'b0, f_takes};
        if (take_t && !hold) begin
            f_have_k <= 1'b1;
            f_last_k <= k;
        end
        if ((take_dio && !hold) || hold) f_dio_done <= 1'b1;
        if (ev_valid_i && ev_ready_o) f_loaded <= 1'b0;
        else if (load && ev_valid_i)  f_loaded <= 1'b1;
        if (load) begin
            f_e_q      <= ev_data_i;
            f_items    <= ev_valid_i ? f_count(ev_data_i, ev_timers_i) : 4'd0;
            f_taken    <= 4'd0;
            f_have_k   <= 1'b0;
            f_dio_done <= 1'b0;
        end
        if (rst) begin
            f_loaded <= 1'b0;
            f_items <= 4'd0;
            f_taken <= 4'd0;
            f_have_k <= 1'b0;
            f_dio_done <= 1'b0;
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && f_v_q && !f_r_q) assume(ev_valid_i && ev_data_i == f_d_q && ev_timers_i == f_t_q);
        if (ev_valid_i && ev_timers_i) assume((ev_data_i[2*NT+25 -: NT] | ev_data_i[NT+25 -: NT]) != {NT{1'b0}});

        if (f_past_valid && !rst && !f_rst_q) begin
            assert(f_takes <= 3'd1);
            if (more || any_t || dio_q || rep_q || hb_q) assert(f_takes == 3'd1);
            if (!RANK_IDX) assert(!hold);
            if (take_t && f_have_k && !hold) assert(k > f_last_k);
            if (take_t) assert(k < NT && low == ({{(NT-1){1'b0}}, 1'b1} << k));
            if (!RANK_IDX) begin
                // the DIG_IO value ranks by ID against the timers (read only with a value)
                if (dio_q)
                    for (f_j2 = 0; f_j2 < NT; f_j2 = f_j2 + 1)
                        assert(ranks[f_j2] == (IDS[6*f_j2 +: 6] <= dio_id_q));
                if (take_t && dio_q) assert(!(dio_id_q < k_id));
            end else begin
                // at stage A: a timer goes on to stage B ahead of the waiting value only
                // with an ID not above it; when the value goes, the timer in stage A (a
                // hold) and every timer left have IDs above it
                if (a_t_q && !hold && dio_q) assert(!(dio_id_q < f_a_id));
                if (hold) assert(dio_id_q < f_a_id);
                if ((hold || take_dio) && any_t) assert(dio_id_q < k_id);
            end
            if (take_dio && !hold && f_have_k) assert(!(dio_id_q < IDS[6*f_last_k +: 6]));
            if (take_dio && !hold && any_t) assert(dio_id_q < k_id);
            if (take_rep) assert(!any_t && !dio_q);
            // the DIG_IO value goes once: taken (or passed by a hold), it is no longer waiting
            if (f_dio_done) assert(!dio_q);
            if (take_hb) assert(!any_t && !dio_q && !rep_q);
            // nothing lost or repeated: the entry's items, one each, then the next entry
            assert(f_taken <= f_items);
            assert(f_taken + f_left(rem) == f_items);
            if (next) assert(f_taken + {1'b0, f_takes} == f_items);
            // each entry loaded once and taken once, after or as it loads; the copies'
            // form takes it as it loads, the memory form an entry without timer events too
            assert(f_loaded == held);
            if (load && ev_valid_i) assert(!f_loaded);
            if (ev_valid_i && ev_ready_o) assert(f_loaded || load);
            if (!MEM || !(ev_valid_i && ev_timers_i)) assert(ev_ready_o == next);
            if (f_loaded) assert(ev_valid_i && ev_timers_i && ev_data_i == f_e_q);
            // stage A's r, f and T are its entry's
            if (a_t_q) assert(ent_r == f_e_q[2*NT+25 -: NT] && ent_f == f_e_q[NT+25 -: NT] &&
                              ent_t == f_e_q[15:0]);
            if (MEM && (a_t_q || any_t)) assert(f_loaded);
            // a clock with a timer in stage A is never one with next (the runs' bits' port
            // reads on the one and the entry loads on the other)
            if (MEM && a_t_q) assert(!next);
            if (!MEM) begin
                assert(empty_o == (!any_t && !dio_q && !rep_q && !hb_q));
                assert(any_t_q == |rem);
            end else begin
                assert(any_t == |rem);
                if (empty_o) assert(!any_t && !dio_q && !rep_q && !hb_q);
                // nothing left but not yet "no item left": the clock after a last timer item
                if (!empty_o && !any_t && !dio_q && !rep_q && !hb_q) assert(a_t_q && !more);
            end
        end
    end

    // What a hold passes to stage B (RANK_IDX): the value alone, stage A's timer kept
    // for the next clock; a timer leaving stage A on another clock passes alone.
    reg       f_hold_q, f_at_q;
    reg [5:0] f_hk_q, f_hid_q;
    always @(posedge clk) begin
        f_hold_q <= hold && !rst;
        f_at_q   <= a_t_q && !hold && !rst;
        f_hk_q   <= a_k_q;
        f_hid_q  <= dio_id_q;
    end
    generate
        if (RANK_IDX) begin : g_f_hold
            always @(*) if (f_past_valid && !f_rst_q && !rst)
                cover(hold && !any_t);                         // a hold of the entry's last timer
        end
    endgenerate
    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        if (f_hold_q) assert(b_dio_q && !b_ord_q && !b_rdone_q && !b_free_q && b_id_q == f_hid_q &&
                             a_t_q && a_k_q == f_hk_q);
        if (f_at_q) assert(!b_dio_q && b_k_q == f_hk_q);
    end

    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover((take_dio || hold) && any_t);                    // the DIG_IO value between timers
        cover(take_hb && f_items == 4'd5);                     // a full entry's last item
        cover(b_ord_q && !b_rep_q && !b_hb_q && b_res_q == 16'd0 && rflx_valid_q == 1'b0);  // a timeout's item
    end

    // The runs' HOST and RFLX bits' memory form (MEM_TIMERS lowered by the prove_mem and
    // cover_mem tasks). Starts are free but never come while hold_o (the top's parser hold)
    // and only for an idle timer, which is busy from its start until its finish goes through
    // stage A (earlier than the real release, its result's delivery: a weaker assumption);
    // a run's one finish (f, with or without r) comes in an entry offered after its start
    // (f_busy is a flop) and before the run's next. Asserted: the bits a finish has in
    // stage B (read in stage A) are its timer's last start's (a shadow per timer), and so
    // are its packet, strobe and release there; hold_o is exactly "a write is pending"; the
    // pending word is its timer's last start's and no entry with that timer's finish was
    // loaded since it (so the write lands first: on the next load's clock at the latest,
    // which has no timer in stage A); every busy timer's word not pending is in the memory;
    // the memory's address on a clock with a timer in stage A is that timer's.
    generate
        if (MEM) begin : g_f_hr
            reg  [NT-1:0] f_busy, f_fsent, f_sh_h, f_sh_r, f_via_pend;
            wire [NT-1:0] f_fin_in = ev_data_i[NT+25 -: NT];
            wire [NT-1:0] f_start  = start_i ? {{(NT-1){1'b0}}, 1'b1} << start_idx_i : {NT{1'b0}};
            // (a finish leaves stage A on a clock without a hold)
            wire [NT-1:0] f_done   = a_t_q && at(ent_f) && !hold ? {{(NT-1){1'b0}}, 1'b1} << a_k_q : {NT{1'b0}};
            reg           f_bfin_q;  // stage B has a finish (f_bk_q's)
            reg  [5:0]    f_bk_q;
            always @(posedge clk) begin
                f_bfin_q <= a_t_q && at(ent_f) && !hold && !rst;
                f_bk_q   <= a_k_q;
                f_busy  <= (f_busy & ~f_done) | f_start;
                f_fsent <= (f_fsent | (load && ev_valid_i && ev_timers_i ? f_fin_in : {NT{1'b0}})) & ~f_start;
                if (start_i) begin
                    f_sh_h     <= (f_sh_h & ~f_start) | (f_start & {NT{start_host_i}});
                    f_sh_r     <= (f_sh_r & ~f_start) | (f_start & {NT{start_rflx_i}});
                    f_via_pend <= (f_via_pend & ~f_start) | (f_start & {NT{a_t_q}});
                end
                if (rst) begin
                    f_busy  <= {NT{1'b0}};
                    f_fsent <= {NT{1'b0}};
                end
            end
            always @(*) begin
                assume(!(start_i && hold_o));
                if (start_i) assume(start_idx_i < NT && (f_busy & f_start) == {NT{1'b0}});
                if (ev_valid_i && ev_timers_i && !f_loaded) assume((f_fin_in & ~(f_busy & ~f_fsent)) == {NT{1'b0}});
                if (f_past_valid && !rst && !f_rst_q) begin
                    assert(hold_o == g_hr.hp_q);
                    if (g_hr.hp_q) begin
                        assert(g_hr.hp_k_q < NT);
                        assert(f_busy[g_hr.hp_k_q] && !f_fsent[g_hr.hp_k_q]);
                        assert(g_hr.hp_d_q == {f_sh_h[g_hr.hp_k_q], f_sh_r[g_hr.hp_k_q]});
                    end
                    if (a_t_q) assert(g_hr.hr_a == a_k_q);
                    if (a_t_q && at(ent_f)) assert(f_busy[a_k_q] && f_fsent[a_k_q]);
                    if (b_rep_q || b_hb_q) assert(order_valid_o);  // whatever word the port read
                    if (f_bfin_q) begin
                        assert(g_hr.hr_rd_q == {f_sh_h[f_bk_q], f_sh_r[f_bk_q]});
                        assert(order_valid_o == f_sh_h[f_bk_q] && b_rdone_w == f_sh_r[f_bk_q] &&
                               rflx_done_o == (f_sh_r[f_bk_q] && !f_sh_h[f_bk_q]));
                    end
                end
            end
            genvar f_g;
            for (f_g = 0; f_g < NT; f_g = f_g + 1) begin : g_f_t
                always @(*) if (f_past_valid && !rst && !f_rst_q) begin
                    if (f_busy[f_g] && !(g_hr.hp_q && g_hr.hp_k_q == f_g))
                        assert(g_hr.hr_mem[f_g] == {f_sh_h[f_g], f_sh_r[f_g]});
                    if (rem_q[f_g] && ent_f[f_g]) assert(f_busy[f_g] && f_fsent[f_g]);
                    if (a_t_q && a_k_q == f_g && at(ent_f)) assert(f_busy[f_g] && f_fsent[f_g]);
                end
            end
            always @(*) if (f_past_valid && !f_rst_q && !rst) begin
                cover(a_t_q && at(ent_f) && f_via_pend[a_k_q] && b_ord_q == 1'b0);  // a pending start's finish
                cover(start_i && a_t_q);                                             // a start that waits
                cover(held && !any_t && !empty_o && f_items == 4'd2 && a_t_q && b_ord_q);    // a held entry's last item in stage A
            end
        end
    endgenerate
