// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_reply_slot (included at the end of the module under `ifdef FORMAL).
// The neighbours are assumed as brainstem_dio has them: the parser hands a packet over
// (pkt_valid_i) only on a clock after one with hold_o 0 and without pkt_valid_i (bsd_parser's
// props prove both), and neither in reset nor on the clock after it (a packet takes at least
// two bytes);
// stage 2 (s2_valid_i) is exactly the clock after pkt_valid_i (bsd_exec: a flop, reset);
// reply_i and dio_rflx_i only with s2_valid_i, reply_n_i <= 8; soft_reset_i (a cmdRESET in
// stage 2, which has no reply) only with s2_valid_i and without reply_i, and rst (the core's
// reset) on the next clock; rep_done_i only while
// rep_req_o (bsd_pkt_tx tells only a waiting source); swap_i only with rst. A reference holds at most one reply:
// after reset the slot holds the power-up message (A, 2, CMD_MSG, statePowerReset); a reply
// from stage 2 fills it with stage 2's N and bytes, rep_done_i empties it. Asserted: rep_req_o
// equals the reference's full flag and, while full, the outputs its contents (so a reply is
// held unchanged until taken, and each reply gives exactly one request: it rises the clock
// after stage 2 and falls only the clock after its done); rep_new_o (the event queue's
// reply bit) is exactly the clock the slot fills, the power-up message's included unless
// swap_i came with its reset (the transmitter sends it already); a DIG_IO
// RFLX value is an event of exactly the clock after stage 2 with stage 2's ID and level; stage
// 2 always finds the slot free (nothing is overwritten or lost); hold_o = a packet in stage 2
// or the slot full or the clock after soft_reset_i, exactly.
    reg                f_past_valid = 1'b0;
    reg                f_rst_q, f_pkt_q, f_req_q, f_done_q, f_reply_q, f_hold_q, f_srst_q, f_swap_q;
    reg                f_rep_full;
    reg [3:0]          f_n;
    reg [31:0]         f_data, f_tail;
    reg                f_dio_q;
    reg [5:0]          f_id_q;
    reg                f_val_q;
    reg [3:0]          f_n_q;
    reg [31:0]         f_data_q, f_tail_q;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q   <= rst;
        f_swap_q  <= swap_i;
        f_pkt_q   <= pkt_valid_i && !rst;
        f_req_q   <= rep_req_o;
        f_done_q  <= rep_done_i;
        f_reply_q <= reply_i;
        f_hold_q  <= hold_o;
        f_srst_q  <= soft_reset_i && !rst;
        f_n_q     <= rep_n_o;
        f_data_q  <= rep_data_o;
        f_tail_q  <= rep_tail_o;
        if (rep_done_i) f_rep_full <= 1'b0;
        if (reply_i) begin
            f_rep_full <= 1'b1;
            f_n    <= reply_n_i;
            f_data <= reply_data_i;
            f_tail <= reply_tail_i;
        end
        f_dio_q   <= dio_rflx_i && !rst;
        f_id_q    <= dio_id_i;
        f_val_q   <= dio_val_i;
        if (rst) begin
            f_rep_full <= 1'b1;
            f_n        <= 4'd2;
            f_data     <= {CMD_MSG, MSG_STATE_POWER_RESET, 16'd0};
            f_tail     <= 32'd0;
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && pkt_valid_i) assume(!f_hold_q && !f_pkt_q);
        if (rst || f_rst_q) assume(!pkt_valid_i);  // the parser needs two bytes after reset
        assume(s2_valid_i == (f_past_valid && f_pkt_q));
        if (reply_i || dio_rflx_i) assume(s2_valid_i);
        if (soft_reset_i) assume(s2_valid_i && !reply_i);
        if (f_past_valid && f_srst_q) assume(rst);
        assume(reply_n_i <= 4'd8);
        if (rep_done_i) assume(rep_req_o);
        if (swap_i) assume(rst);

        if (f_past_valid) begin
            assert(rep_req_o == f_rep_full);
            if (f_rep_full) begin
                assert(rep_n_o == f_n);
                assert(rep_data_o == f_data);
                assert(rep_tail_o == f_tail);
            end
            assert(dio_new_o == f_dio_q);
            if (f_dio_q) assert(dio_id_o == f_id_q && dio_val_o == f_val_q);
            assert(hold_o == (s2_valid_i || rep_req_o || f_srst_q));
            // Stage 2 finds the slot free.
            if (s2_valid_i) assert(!rep_req_o);
            // The reply's event: the clock the request rises (the power-up message's too).
            assert(rep_new_o == (rep_req_o && (f_rst_q ? !f_swap_q : !f_req_q || f_done_q)));
            if (!f_rst_q) begin
                // A request rises only the clock after a reply, falls only after its done;
                // while it waits its packet does not change.
                if (rep_req_o && !f_req_q) assert(f_reply_q);
                if (!rep_req_o && f_req_q) assert(f_done_q);
                if (f_req_q && !f_done_q)
                    assert(rep_n_o == f_n_q && rep_data_o == f_data_q && rep_tail_o == f_tail_q);
            end
            // Induction: reply_q is the request only on the clock after stage 2.
            if (reply_q) assert(!rep_wait_q && f_reply_q && !f_rst_q);
        end
    end

    // Covers: the power-up message taken, then a reply waiting with an RFLX value's event,
    // a second reply after the first is taken; a reply taken on the clock it is requested.
    reg [1:0] f_taken = 2'd0;
    always @(posedge clk)
        if (rst) f_taken <= 2'd0;
        else if (rep_done_i && f_taken != 2'd3) f_taken <= f_taken + 2'd1;
    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover(f_taken == 2'd1 && rep_req_o && dio_new_o && rep_n_o == 4'd8);
        cover(f_taken == 2'd2 && rep_req_o);
        cover(reply_q && rep_done_i);
    end
