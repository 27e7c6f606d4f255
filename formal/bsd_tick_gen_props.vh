// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_tick_gen (included at the end of its g_accumulator block under
// `ifdef FORMAL). In every window of F_WINDOW clocks (define F_WINDOW, set per task) the
// strobe count lies between floor and ceil of F_WINDOW * RATE_HZ / CLK_HZ; so it never
// strays by 1 or more from the ideal. The accumulator stays below MOD (induction).
`ifndef F_WINDOW
`define F_WINDOW 16
`endif
            localparam integer F_W  = `F_WINDOW;
            localparam integer F_LO = (F_W * INC) / MOD;
            localparam integer F_HI = (F_W * INC + MOD - 1) / MOD;
            reg            f_past_valid = 1'b0;
            reg [F_W-1:0]  f_hist;
            reg [7:0]      f_n;      // clocks since reset, saturating
            integer        f_i, f_cnt;

            always @(posedge clk) begin
                f_past_valid <= 1'b1;
                f_hist <= {f_hist[F_W-2:0], tick_q};
                if (f_n != 8'hFF) f_n <= f_n + 8'd1;
                if (rst) f_n <= 8'd0;
            end

            always @(*) begin
                if (!f_past_valid) assume(rst);
                f_cnt = 0;
                for (f_i = 0; f_i < F_W; f_i = f_i + 1)
                    f_cnt = f_cnt + f_hist[f_i];
                if (f_past_valid) begin
                    assert(acc_q < MOD);  // as a number: MOD_W is 0 when MOD is 2^W
                    if (f_n > F_W) begin
                        assert(f_cnt >= F_LO);
                        assert(f_cnt <= F_HI);
                    end
                end
            end

            always @(*) if (f_past_valid && f_n > F_W) begin
                cover(f_cnt == F_LO);
                cover(f_cnt == F_HI);
            end
