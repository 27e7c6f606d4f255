// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_age_arb (included at the end of the module under `ifdef FORMAL).
// A reference model keeps each pending requester's age (clocks since it was born, saturating
// at 15). Among the candidates (req_q & ~exclude_i) the grant goes to the oldest, the lowest
// index on ties; it is one-hot or zero, and zero only when there is no candidate. The ages
// are exact while under 15: requests are assumed to drop within 14 clocks (a longer wait
// would need a wider age; the design's matrix has no such limit).
    reg          f_past_valid = 1'b0;
    reg  [3:0]   f_age [0:K-1];
    integer      f_i, f_j, f_c;  // f_c: the clocked block's own loop variable

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        for (f_c = 0; f_c < K; f_c = f_c + 1)
            if (born[f_c]) f_age[f_c] <= 4'd0;
            else if (req_q[f_c] && f_age[f_c] != 4'd15) f_age[f_c] <= f_age[f_c] + 4'd1;
    end

    // j ranks before i: older, or born on the same clock with a lower index.
    function f_before(input integer j, input integer i);
        f_before = (f_age[j] > f_age[i]) || (f_age[j] == f_age[i] && j < i);
    endfunction

    always @(*) begin
        f_j = 0;
        if (!f_past_valid) assume(rst);
        for (f_i = 0; f_i < K; f_i = f_i + 1)
            if (req_q[f_i]) assume(f_age[f_i] != 4'd15);
        if (f_past_valid && !rst) begin
            // One-hot or zero; only to a candidate; zero only with no candidate.
            assert((gnt & (gnt - 1'b1)) == {K{1'b0}});
            assert((gnt & ~cand) == {K{1'b0}});
            assert((cand == {K{1'b0}}) == (gnt == {K{1'b0}}));
            for (f_i = 0; f_i < K; f_i = f_i + 1)
                if (req_q[f_i]) assert(!older_q[K*f_i + f_i]);  // never older than itself
            for (f_i = 0; f_i < K; f_i = f_i + 1)
                for (f_j = 0; f_j < K; f_j = f_j + 1)
                    if (f_i != f_j && req_q[f_i] && req_q[f_j]) begin
                        // Induction: the age matrix agrees with the reference ages.
                        assert(older_q[K*f_i + f_j] == f_before(f_j, f_i));
                        // The grant goes to the candidate that ranks first.
                        if (gnt[f_i] && cand[f_j]) assert(f_before(f_i, f_j));
                    end
        end
    end

    always @(*) if (f_past_valid && !rst) begin
`ifndef F_ARB_IN_TX
        // Not in bsd_tx's job: with K = 2 and sources that drop their request after their
        // done_o, an older source 1 is never a candidate together with source 0.
        cover(gnt[K-1] && cand[0]);                  // a higher index wins by age
`endif
        cover(gnt[0] && cand[K-1] && f_age[0] == f_age[K-1]);  // a tie goes to the lower index
    end
