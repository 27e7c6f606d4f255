// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_pkt_tx (included at the end of the module under `ifdef FORMAL).
// The output queue's head is assumed to obey AXI-Stream (offered until taken, unchanged);
// the reply slot and the heartbeat hold their packet while an item of theirs is offered or
// its packet is going out (they change only after its done); rep_n_i <= 8; m_axis_tready
// free. Asserted (PROTOCOL.md §2, §5): m_axis obeys AXI-Stream (tvalid held until taken,
// tdata and tlast unchanged while stalled); every packet is `A, N, ..` with tlast exactly
// on byte N + 1 (N as the item's source gives it); one item per packet: an item is taken
// only on a clock with no byte left to send but the last one's handshake, and free_o (the
// output queue's pop) says exactly that; the source's done comes exactly with its packet's
// last handshake. cmdRESET (flush_i, a pulse while the sources and the queue are reset around
// it; never while a reply is on offer or going out, decision 14): no item is taken on its
// clock; a packet on offer with no byte taken and none taken now becomes the power-up message
// (swap_o, exactly then), which the reply slot holds from the next clock, and reports done;
// a packet already under way is finished and reports no done.
    reg        f_past_valid = 1'b0;
    reg        f_rst_q, f_iv_q, f_ir_q, f_mv_q, f_mr_q, f_ml_q;
    reg [29:0] f_id_q;
    reg [7:0]  f_md_q;
    reg [3:0]  f_pos, f_n;
    reg [1:0]  f_kind;
    reg        f_busy;   // a packet is going out
    reg        f_credit; // and reports its done at the end
    reg        f_flush_q, f_flushed;
    reg        f_swap_q = 1'b0;
    reg [31:0] f_rd, f_rt;
    reg [7:0]  f_ht;

    wire f_hs = m_axis_tvalid && m_axis_tready;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_iv_q <= item_valid_i; f_ir_q <= item_ready_o; f_id_q <= item_data_i;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata; f_ml_q <= m_axis_tlast;
        f_flush_q <= flush_i && !rst;
        f_swap_q  <= 1'b0;
        // the clock after a swap: the reply slot now holds the power-up message
        if (f_swap_q) begin
            f_rd <= rep_data_i;
            f_rt <= rep_tail_i;
        end
        if (flush_i && f_busy && !rst) begin
            f_flushed <= 1'b1;
            if (f_pos == 4'd0 && !m_axis_tready) begin
                f_swap_q <= 1'b1;
                f_kind   <= 2'd1;
                f_n      <= MSG_N[3:0];
            end else begin
                f_credit <= 1'b0;
            end
        end
        if (f_hs) begin
            f_pos <= f_pos + 4'd1;
            if (m_axis_tlast) f_busy <= 1'b0;
        end
        if (item_valid_i && item_ready_o) begin
            f_busy <= 1'b1;
            f_credit  <= 1'b1;
            f_flushed <= 1'b0;
            f_pos  <= 4'd0;
            f_kind <= item_data_i[29:28];
            f_n    <= item_data_i[29:28] == 2'd0 ? 4'd4 : item_data_i[29:28] == 2'd1 ? rep_n_i : 4'd2;
            f_rd   <= rep_data_i;
            f_rt   <= rep_tail_i;
            f_ht   <= hb_type_i;
        end
        if (rst) begin
            f_busy <= 1'b0;
            f_pos  <= 4'd0;
        end
    end

    reg [7:0]  f_byte;
    reg [12:0] f_sel;
    integer    f_i;
    always @(*) begin
        case (f_kind)
            2'd0: case (f_pos)
                4'd2: f_byte = CMD_DEV_VAL;
                4'd3: f_byte = {2'b00, id_q};
                4'd4: f_byte = result_q[15:8];
                default: f_byte = result_q[7:0];
            endcase
            2'd1: f_byte = f_pos >= 4'd9 ? f_rt[7:0] : {f_rd, f_rt} >> (8 * (4'd9 - f_pos));
            default: f_byte = f_pos == 4'd2 ? CMD_HB : f_ht;
        endcase
        // the flag of the byte offered; a packet's last byte has none
        f_sel = 13'd0;
        f_sel[12] = f_pos == 4'd0;
        f_sel[11] = f_pos == 4'd1;
        if (f_kind == 2'd0) f_sel[10:8] = {f_pos == 4'd2, f_pos == 4'd3, f_pos == 4'd4};
        for (f_i = 0; f_i < 7; f_i = f_i + 1)
            f_sel[1 + f_i] = f_kind == 2'd1 && f_pos == f_i + 2;
        if (f_kind == 2'd2) f_sel[0] = f_pos == 4'd2;
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && !f_flush_q && f_iv_q && !f_ir_q) assume(item_valid_i && item_data_i == f_id_q);
        assume(item_data_i[29:28] != 2'd3);
        assume(rep_n_i <= 4'd8);
        if (f_past_valid && f_flush_q) assume(!flush_i);
        if (f_busy && f_kind == 2'd1) assume(!flush_i);
        // the reply slot and the heartbeat keep their packet while it goes out
        if (f_past_valid && !f_rst_q && f_busy) begin
            if (f_kind == 2'd1 && !f_swap_q) assume(rep_n_i == f_n && rep_data_i == f_rd && rep_tail_i == f_rt);
            if (f_kind == 2'd2 && !f_flushed) assume(hb_type_i == f_ht);
        end

        if (f_past_valid && !rst && !f_rst_q) begin
            if (f_mv_q && !f_mr_q) assert(m_axis_tvalid && m_axis_tdata == f_md_q && m_axis_tlast == f_ml_q);
            assert(m_axis_tvalid == f_busy);
            if (f_busy) begin
                assert(rem_q == f_n - f_pos && kind_q == f_kind && f_kind != 2'd3);
                assert(f_n <= 4'd8 && last_q == (f_pos == f_n + 4'd1));
                assert(credit_q == f_credit && first_q == (f_pos == 4'd0));
                assert(m_axis_tlast == (f_pos == f_n + 4'd1));
                assert(f_pos <= f_n + 4'd1);
                if (f_pos == 4'd0) assert(m_axis_tdata == MODULE_ADDR[7:0]);
                if (f_pos == 4'd1) assert(m_axis_tdata == {4'd0, f_n});
                // the data bytes: each source's, by position
                if (f_kind == 2'd2) assert(hb_type_q == f_ht && f_n == 4'd2);
                if (f_kind == 2'd0) assert(f_n == 4'd4);
                if (f_pos >= 4'd2) assert(m_axis_tdata == f_byte);
                // the byte flags: exactly the byte offered
                assert({sel_addr_q, sel_n_q, sel_tcmd_q, sel_tid_q, sel_thi_q, sel_rep_q, sel_hcmd_q} == f_sel);
            end
            if (item_ready_o) assert(!flush_i && (!f_busy || (f_hs && m_axis_tlast)));
            assert(swap_o == (flush_i && f_busy && f_pos == 4'd0 && !m_axis_tready));
            assert(free_o == (!f_busy || (f_hs && m_axis_tlast)));  // the output queue's pop
            assert((timer_done_o || reply_done_o || hb_done_o) == (f_hs && m_axis_tlast && f_credit));
            if (f_hs && m_axis_tlast && f_credit)
                assert(timer_done_o == (f_kind == 2'd0) && reply_done_o == (f_kind == 2'd1) &&
                       hb_done_o == (f_kind == 2'd2));
        end
    end

    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover(f_hs && m_axis_tlast && f_kind == 2'd1 && f_n == 4'd8);   // a cmdDEBUG echo of 8
        cover(f_hs && m_axis_tlast && item_ready_o);                     // back to back
        cover(timer_done_o && f_past_valid);
        cover(f_hs && m_axis_tlast && f_flushed && f_kind == 2'd0);     // a timer packet finished after a flush
        cover(reply_done_o && f_flushed);                                // a swapped packet sent
        cover(flush_i && f_busy && f_pos > 4'd1 && !m_axis_tready);      // a flush during a stall past N
    end
