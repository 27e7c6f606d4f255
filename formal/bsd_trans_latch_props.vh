// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_trans_latch (included at the end of the module under `ifdef FORMAL).
// f_ref is the level the latch compares with: the level at arming, then each sample's
// (every sample's, watched or not: watch_i changes only with an arm at the top).
// At most one fire per arm; a fire needs a sampled level that differs from f_ref and
// matches TRG (so the level present at arming never fires by itself); an arm on the
// clock of a matching edge wins (no fire on the next clock, armed again).
    reg f_past_valid = 1'b0;
    reg f_arm_q = 1'b0, f_fire_q = 1'b0, f_rst_q = 1'b0;
    reg f_fired;   // a fire since the last arm
    reg f_ref;
    // The fire the RTL works out in sample_step: a watched, armed pin's sample that changes
    // from the previous one to the TRG level.
    wire [WIDTH-1:0] fire = armed_q & watch_i & {WIDTH{sample_i}} & ~(level_i ^ trg_i) & (prev_q ^ trg_i);

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_arm_q  <= arm_i;
        f_fire_q <= fire && !arm_i;  // an arm on the same clock wins
        f_rst_q  <= rst;
        if (arm_i) begin
            f_fired <= 1'b0;
            f_ref   <= level_i;
        end else begin
            if (fire) f_fired <= 1'b1;
            if (sample_i) f_ref <= level_i;
        end
        if (rst) f_fired <= 1'b1;  // no arm yet
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && !rst) begin
            assert(fire_o == f_fire_q);
            if (fire) begin
                assert(!f_fired);                    // one fire per arm
                assert(level_i != f_ref);            // a change from the reference level
                assert(level_i == trg_i && watch_i && sample_i);
            end
            if (f_arm_q) begin
                assert(!fire_o);                     // re-arm wins on the same clock
                assert(armed_q);
            end
            // Induction: armed exactly while no fire since the last arm.
            assert(armed_q == !f_fired);
            if (armed_q) assert(prev_q == f_ref);
        end
    end

    reg f_fires = 1'b0;
    always @(posedge clk) if (fire_o) f_fires <= 1'b1;
    always @(*) if (f_past_valid && !rst) begin
        cover(fire_o);
        cover(f_fires && fire_o && !trg_i);          // a second fire (after a re-arm)
        cover(f_arm_q && level_i == trg_i && watch_i && sample_i && armed_q && level_i != prev_q);
    end
