// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_uart_rx (included at the end of the module under `ifdef FORMAL).
// The output is a one-clock strobe with no back-pressure (valid_o / frame_err_o; no ready,
// by design: a byte not taken on its valid_o clock is gone, data_o keeps it until the next
// one). The line rx_i is any sequence of levels, changing on any clock.
// Reference: f_h[k] is the synchronized line k clocks ago (rx_i delayed 2 + k clocks, reset
// to idle like the design's synchronizer). The documented framing: a frame starts on a clock
// where the synchronized line is low (edge E), its start bit is sampled low HALF clocks later,
// data bit i at HALF + (i + 1) * DIV, the stop bit at HALF + 9 * DIV; the strobe follows
// one clock after the stop sample. Asserted: valid_o only after such a frame with the stop
// bit 1, and data_o = the data samples; frame_err_o only after such a frame with the stop bit
// 0; never a strobe sooner than a whole frame after the last one; after a frame error no
// strobe until the line has been seen idle (a break gives one error); data_o changes only
// with valid_o; the counters stay in range. Induction: the shift register holds the data
// samples so far and the synchronizer matches the reference.
    localparam integer F_FR = HALF + 9 * DIV + 2;  // history: edge .. stop sample, and the strobe's clock
    reg              f_past_valid = 1'b0;
    reg              f_rst_q;
    reg              f_s1, f_s2;       // the reference synchronizer
    reg  [F_FR-2:0]  f_hist;           // f_s2 of the earlier clocks, the newest in bit 0
    wire [F_FR-1:0]  f_h = {f_hist, f_s2};
    reg  [7:0]       f_dq;
    reg  [7:0]       f_gap;            // clocks since the last strobe, minus 1 (saturating)
    reg              f_brk;            // a frame error, and the line not seen idle since
    reg  [7:0]       f_data;           // the data samples of the frame that ends now
    integer          f_i, f_j;
    wire             f_strobe = valid_o || frame_err_o;
    // Clocks since this frame's edge (state START, DATA, STOP), from the design's state.
    reg  [7:0]       f_el;
    always @(*) begin
        case (state_q)
            ST_START: f_el = HALF - cnt_q;
            ST_DATA:  f_el = HALF + bit_q * DIV + DIV - cnt_q;
            ST_STOP:  f_el = HALF + 8 * DIV + DIV - cnt_q;
            default:  f_el = 8'd0;
        endcase
        for (f_j = 0; f_j < 8; f_j = f_j + 1)
            f_data[f_j] = f_h[1 + (8 - f_j) * DIV];
    end

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_s1 <= rx_i;
        f_s2 <= f_s1;
        f_hist <= {f_hist[F_FR-3:0], f_s2};
        f_dq <= data_o;
        if (f_strobe) f_gap <= 8'd0;
        else if (f_gap != 8'hFF) f_gap <= f_gap + 8'd1;
        if (frame_err_o && !f_s2) f_brk <= 1'b1;
        else if (f_s2) f_brk <= 1'b0;
        if (rst) begin
            f_s1 <= 1'b1;
            f_s2 <= 1'b1;
            f_hist <= {(F_FR - 1){1'b1}};
            f_gap <= 8'hFF;
            f_brk <= 1'b0;
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        // Induction: the clock after a reset.
        if (f_past_valid && f_rst_q)
            assert(state_q == ST_IDLE && !valid_o && !frame_err_o && meta_q && rx_q && f_s1 && f_s2
                   && f_h == {F_FR{1'b1}} && !f_brk);
        if (f_past_valid && !f_rst_q) begin
            // The synchronizer is two flops.
            assert(meta_q == f_s1 && rx_q == f_s2);
            // Counters and state in range.
            assert(state_q <= ST_BREAK);
            assert(cnt_q < DIV);
            if (state_q == ST_START) assert(cnt_q < HALF);
            // Strobes: one at a time, a whole frame apart, only after a frame.
            assert(!(valid_o && frame_err_o));
            if (f_strobe) begin
                assert(f_gap >= F_FR - 2);
                assert(!f_brk);
                assert(f_h[F_FR - 1] == 1'b0);          // the edge clock: line low
                assert(f_h[F_FR - 1 - HALF] == 1'b0);   // start bit at its middle
                assert(f_h[1] == valid_o);              // the stop bit: 1 for a byte, 0 for an error
            end
            if (valid_o) assert(data_o == f_data);
            else assert(data_o == f_dq);
            // Induction: the frame in progress matches the reference.
            if (state_q == ST_START || state_q == ST_DATA || state_q == ST_STOP) begin
                assert(f_el <= F_FR - 2);
                assert(f_h[f_el] == 1'b0);
                assert({1'b0, f_gap} + 9'd1 >= {1'b0, f_el});
                assert(!f_brk);
                if (state_q == ST_DATA) assert(bit_q * DIV + DIV - cnt_q <= DIV * 8);
            end
            if (state_q == ST_DATA || state_q == ST_STOP) begin
                assert(f_h[f_el - HALF] == 1'b0);
                for (f_i = 0; f_i < 8; f_i = f_i + 1)
                    if (state_q == ST_STOP || f_i < bit_q)
                        assert(shift_q[f_i + (state_q == ST_STOP ? 0 : 8 - bit_q)]
                               == f_h[f_el - HALF - (f_i + 1) * DIV]);
            end
            if (state_q == ST_BREAK) assert(f_brk || frame_err_o);
            else assert(!f_brk);
        end
    end

    reg f_byte_seen = 1'b0;
    always @(posedge clk) if (valid_o) f_byte_seen <= 1'b1;
    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(valid_o && data_o == 8'hA5);                   // a byte received
        cover(frame_err_o);                                   // a framing error
        cover(state_q == ST_BREAK && f_gap == 8'd0 && !rx_q); // a break: the line still low after the error
        cover(state_q == ST_START && cnt_q == 0 && rx_q);     // a glitch: start bit high again at its middle
    end
