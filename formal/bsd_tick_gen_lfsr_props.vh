// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_tick_gen's LFSR divider (included at the end of its g_lfsr block
// under `ifdef FORMAL). A reference divider f_k counts the clocks since reset modulo MOD0,
// as the accumulator does with RATE/g = 1 (it starts at 0 and strobes on the clock after
// MOD0 - 1). Asserted: the strobe exactly on the clock after the reference reaches
// MOD0 - 1; induction: the LFSR holds x^f_k modulo its trinomial.
            reg        f_past_valid = 1'b0;
            // As narrow as MOD0 needs: the power of x below is then a small circuit.
            localparam integer KW = $clog2(MOD0 + 1);
            reg [KW-1:0] f_k;
            reg        f_tick;

            always @(posedge clk) begin
                f_past_valid <= 1'b1;
                f_k    <= f_k == MOD0 - 1 ? {KW{1'b0}} : f_k + 1'b1;
                f_tick <= f_k == MOD0 - 1;
                if (rst) begin
                    f_k    <= {KW{1'b0}};
                    f_tick <= 1'b0;
                end
            end

            always @(*) begin
                if (!f_past_valid) assume(rst);
                if (f_past_valid) begin
                    assert(f_k < MOD0);
                    assert({{(32-LW){1'b0}}, lfsr_q} == lfsr_pow({{(32-KW){1'b0}}, f_k}, LW, LFSR_P));
                    assert(tick_q == f_tick);
                end
            end

            always @(*) if (f_past_valid) cover(tick_q);
