// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_uart_tx (included at the end of the module under `ifdef FORMAL).
// A reference frame: from the clock after a byte is taken, the line carries the start bit
// (0), the 8 data bits LSB first and the stop bit (1), DIV clocks each; the line is high
// whenever no frame is going out. A byte is taken only when the line is idle or on the last
// clock of a stop bit (s_axis_tready exact), so frames never overlap and none is cut short.
// The source obeys AXI-Stream (assumed).
    reg        f_past_valid = 1'b0;
    reg        f_rst_q, f_sv_q, f_sr_q;
    reg [7:0]  f_sd_q;
    reg [9:0]  f_frame;   // stop, data, start: bit 0 goes first
    reg        f_busy;
    reg [3:0]  f_bit;     // bit of the frame on the line
    reg [LW-1:0] f_clk;   // clocks of it so far (LW bits hold DIV - 1)
    wire       f_take = s_axis_tvalid && s_axis_tready;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata;
        if (f_busy) begin
            if (f_clk == DIV[LW-1:0] - 1'b1) begin
                f_clk <= {LW{1'b0}};
                f_bit <= f_bit + 4'd1;
                if (f_bit == 4'd9) f_busy <= 1'b0;
            end else begin
                f_clk <= f_clk + 1'b1;
            end
        end
        if (f_take) begin
            f_frame <= {1'b1, s_axis_tdata, 1'b0};
            f_busy  <= 1'b1;
            f_bit   <= 4'd0;
            f_clk   <= {LW{1'b0}};
        end
        if (rst) f_busy <= 1'b0;
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && f_sv_q && !f_sr_q) begin
            assume(s_axis_tvalid);
            assume(s_axis_tdata == f_sd_q);
        end
        if (f_past_valid && !f_rst_q) begin
            // The line follows the reference frame; idle high.
            assert(tx_o == (f_busy ? f_frame[f_bit] : 1'b1));
            // Ready exactly when idle or on the stop bit's last clock.
            assert(s_axis_tready == (!f_busy || (f_bit == 4'd9 && f_clk == DIV[LW-1:0] - 1'b1)));
            // Induction: the design's counters agree with the reference.
            assert(busy == f_busy);
            if (f_busy) begin
                assert(f_bit <= 4'd9 && f_clk < DIV);
                assert(left_q == 4'd10 - f_bit);
                assert({{(32-LW){1'b0}}, cnt_q} == lfsr_pow({{(32-LW){1'b0}}, f_clk}, LW, LFSR_P));
                assert(end_q == (f_clk == DIV[LW-1:0] - 1'b1));
                assert(shift_q == (({9'h1FF, f_frame} >> (f_bit + 4'd1)) & 9'h1FF));
            end
        end
    end

    reg [1:0] f_frames = 2'd0;
    // Frames taken since reset (a take on a reset clock is no frame: reset overrides it).
    always @(posedge clk)
        if (rst) f_frames <= 2'd0;
        else if (f_take && f_frames != 2'd3) f_frames <= f_frames + 2'd1;
    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(f_take && f_busy && f_frames == 2'd1);   // back to back: the second byte on the stop bit
        cover(f_frames == 2'd2 && !f_busy);             // two frames out, idle again
    end
