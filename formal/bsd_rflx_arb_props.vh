// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_rflx_arb (included at the end of the module under `ifdef FORMAL).
// The sources are assumed to behave as the top's do: a timer keeps timer_req_i[p] up and its
// result unchanged until timer_done_o[p], the DIG_IO slot keeps dio_req_i, dio_id_i and
// dio_val_i until dio_done_o; dio_below_i[p] = dio_id_i < TIMER_ID_BASE + p (bsd_reply_slot's
// job proves it); device IDs are unique (dio_id_i is no timer's ID). Asserted: the grant
// {timer_done_o, dio_done_o} is one-hot or zero, only to a waiting source, zero only when none
// waits (work conserving); it goes to the waiting value with the lowest device ID (the lowest
// timer pin); the clock after a grant rflx_valid_o is 1 with that value's ID and data
// (DIG_IO: {15'd0, val}), and 0 after a clock with no grant (reset: 0, ID 0, data 0): one
// strobe, of one clock, per granted value, so no value is strobed twice and none is strobed
// without its source being told. With F_QUIET (task prove_wait) a source also stays quiet
// for NUM_PINS clocks after its done (a new value cannot come sooner in brainstem_dio: a
// timer needs a new command, the DIG_IO slot a new packet): then no request is lost, each
// is granted within NUM_PINS clocks of its rise, and two strobes on successive clocks carry
// different IDs.
    localparam integer F_NS = NUM_PINS + 1;  // sources: 0 = DIG_IO, 1 + p = timer p
    reg                f_past_valid = 1'b0;
    reg                f_rst_q;
    reg [NUM_PINS-1:0] f_treq_q, f_tdone_q;
    reg [16*NUM_PINS-1:0] f_tres_q;
    reg                f_dreq_q, f_ddone_q, f_dval_q;
    reg [5:0]          f_did_q;
    reg                f_any_q;
    reg [5:0]          f_gid, f_gid_q, f_rid_q;
    reg [15:0]         f_gdata, f_gdata_q;
    reg                f_rv_q;
    wire [F_NS-1:0]    f_req = {timer_req_i, dio_req_i};
    wire [F_NS-1:0]    f_gnt = {timer_done_o, dio_done_o};
    integer            f_c, f_i, f_j, f_k;

    // The granted value's ID and data (the lowest set bit wins, should two be set).
    always @(*) begin
        f_gid   = 6'd0;
        f_gdata = 16'd0;
        for (f_k = NUM_PINS - 1; f_k >= 0; f_k = f_k - 1)
            if (timer_done_o[f_k]) begin
                f_gid   = TIMER_ID_BASE[5:0] + f_k[5:0];
                f_gdata = timer_result_i[16*f_k +: 16];
            end
        if (dio_done_o) begin
            f_gid   = dio_id_i;
            f_gdata = {15'd0, dio_val_i};
        end
    end

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q   <= rst;
        f_treq_q  <= timer_req_i;
        f_tdone_q <= timer_done_o;
        f_tres_q  <= timer_result_i;
        f_dreq_q  <= dio_req_i;
        f_ddone_q <= dio_done_o;
        f_did_q   <= dio_id_i;
        f_dval_q  <= dio_val_i;
        f_any_q   <= |f_gnt;
        f_gid_q   <= f_gid;
        f_gdata_q <= f_gdata;
        f_rv_q    <= rflx_valid_o;
        f_rid_q   <= rflx_id_o;
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        // Sources hold their value until told.
        if (f_past_valid && !f_rst_q) begin
            for (f_i = 0; f_i < NUM_PINS; f_i = f_i + 1)
                if (f_treq_q[f_i] && !f_tdone_q[f_i]) begin
                    assume(timer_req_i[f_i]);
                    assume(timer_result_i[16*f_i +: 16] == f_tres_q[16*f_i +: 16]);
                end
            if (f_dreq_q && !f_ddone_q) begin
                assume(dio_req_i);
                assume(dio_id_i == f_did_q);
                assume(dio_val_i == f_dval_q);
            end
        end
        for (f_i = 0; f_i < NUM_PINS; f_i = f_i + 1)
            assume(dio_below_i[f_i] == (dio_id_i < TIMER_ID_BASE[5:0] + f_i[5:0]));
        assume(dio_id_i < TIMER_ID_BASE[5:0] || dio_id_i >= TIMER_ID_BASE[5:0] + NUM_PINS[5:0]);

        // The grant: one-hot or zero, only to a waiting source, zero only when none waits.
        assert((f_gnt & (f_gnt - 1'b1)) == {F_NS{1'b0}});
        assert((f_gnt & ~f_req) == {F_NS{1'b0}});
        assert((f_req == {F_NS{1'b0}}) == (f_gnt == {F_NS{1'b0}}));
        // Lowest device ID first.
        for (f_j = 0; f_j < NUM_PINS; f_j = f_j + 1) begin
            if (dio_done_o && timer_req_i[f_j]) assert(dio_id_i < TIMER_ID_BASE[5:0] + f_j[5:0]);
            if (timer_done_o[f_j] && dio_req_i) assert(dio_id_i > TIMER_ID_BASE[5:0] + f_j[5:0]);
            if (timer_done_o[f_j]) assert((timer_req_i & ((1 << f_j) - 1)) == {NUM_PINS{1'b0}});
        end

        // The strobe: the clock after a grant, with its value; nothing after no grant.
        if (f_past_valid) begin
            if (f_rst_q) begin
                assert(!rflx_valid_o);
                assert(rflx_id_o == 6'd0);
                assert(rflx_data_o == 16'd0);
            end else begin
                assert(rflx_valid_o == f_any_q);
                if (rflx_valid_o) begin
                    assert(rflx_id_o == f_gid_q);
                    assert(rflx_data_o == f_gdata_q);
                end
            end
        end
    end

`ifdef F_QUIET
    // A source stays quiet for NUM_PINS clocks after its done; then each request is granted
    // within NUM_PINS clocks (N + 1 sources, one grant a clock, none granted twice in that
    // window).
    reg [3:0] f_quiet [0:F_NS-1];  // clocks since its last done (saturating), NUM_PINS after reset
    reg [3:0] f_wait  [0:F_NS-1];  // clocks it has waited without a grant
    always @(posedge clk) begin
        for (f_c = 0; f_c < F_NS; f_c = f_c + 1) begin
            if (f_gnt[f_c]) f_quiet[f_c] <= 4'd0;
            else if (f_quiet[f_c] != 4'd15) f_quiet[f_c] <= f_quiet[f_c] + 4'd1;
            if (f_req[f_c] && !f_gnt[f_c] && f_wait[f_c] != 4'd15) f_wait[f_c] <= f_wait[f_c] + 4'd1;
            else f_wait[f_c] <= 4'd0;
            if (rst) begin
                f_quiet[f_c] <= NUM_PINS;
                f_wait[f_c]  <= 4'd0;
            end
        end
    end
    always @(*) begin
        for (f_i = 0; f_i < F_NS; f_i = f_i + 1) begin
            if (f_past_valid && f_quiet[f_i] < NUM_PINS) assume(!f_req[f_i]);
            if (f_past_valid) begin
                assert(f_wait[f_i] <= NUM_PINS);
                if (f_wait[f_i] == NUM_PINS) assert(f_gnt[f_i]);
                // Induction: a waiting source was granted no sooner than its wait began.
                if (f_req[f_i]) assert(f_quiet[f_i] >= f_wait[f_i]);
            end
        end
        if (f_past_valid && !f_rst_q && f_rv_q && rflx_valid_o) assert(rflx_id_o != f_rid_q);
    end
`endif

    // Covers: every source waiting at once, then strobed on successive clocks (the last,
    // timer 2, three clocks after the DIG_IO value ranked below timer 0); a timer below the
    // DIG_IO value goes first.
    reg [2:0] f_run = 3'd0;
    always @(posedge clk)
        if (rst) f_run <= 3'd0;
        else if (f_run == 3'd0) f_run <= (&f_req && dio_done_o) ? 3'd1 : 3'd0;
        else if (f_run != 3'd7) f_run <= (f_gnt == (1 << f_run)) ? f_run + 3'd1 : 3'd0;
    always @(*) if (f_past_valid && !rst) begin
        cover(f_run == F_NS && rflx_valid_o);
        cover(timer_done_o[0] && dio_req_i);
    end
