// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_msg_merge (included at the end of the module under `ifdef FORMAL).
// The stream input obeys AXI-Stream and req_i stays up until done_o (assumed). Asserted:
// the output obeys AXI-Stream (a stalled byte stays, with its tlast: never switching away
// from it); the message goes out whole, `A, 2, 0x80, CODE` with tlast on CODE, never inside
// a stream packet and never with a stream byte inside it; stream bytes pass unchanged;
// done_o pulses with the message's last handshake.
    reg       f_past_valid = 1'b0;
    reg       f_rst_q, f_sv_q, f_sr_q, f_sl_q, f_mv_q, f_mr_q, f_ml_q, f_req_q, f_done_q;
    reg [7:0] f_sd_q, f_md_q;
    reg [2:0] f_oidx;   // bytes of the current output packet already taken
    reg       f_omsg;   // the current output packet is the message
    wire      f_mhs = m_axis_tvalid && m_axis_tready;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata; f_sl_q <= s_axis_tlast;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata; f_ml_q <= m_axis_tlast;
        f_req_q <= req_i; f_done_q <= done_o;
        if (f_mhs) begin
            if (f_oidx == 3'd0) f_omsg <= msg;
            f_oidx <= m_axis_tlast ? 3'd0 : (f_oidx == 3'd7 ? 3'd7 : f_oidx + 3'd1);
        end
        if (rst) begin
            f_oidx <= 3'd0;
            f_omsg <= 1'b0;
        end
    end

    reg [7:0] f_msg_byte;
    always @(*) begin
        case (f_oidx)
            3'd0:    f_msg_byte = ADDR_OWN;
            3'd1:    f_msg_byte = 8'd2;
            3'd2:    f_msg_byte = 8'h80;
            default: f_msg_byte = MSG_CODE;
        endcase
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q) begin
            if (f_sv_q && !f_sr_q) begin
                assume(s_axis_tvalid);
                assume(s_axis_tdata == f_sd_q);
                assume(s_axis_tlast == f_sl_q);
            end
            if (f_req_q && !f_done_q) assume(req_i);
        end
        if (f_past_valid && !f_rst_q && !rst) begin
            if (f_mv_q && !f_mr_q) begin
                assert(m_axis_tvalid);
                assert(m_axis_tdata == f_md_q);
                assert(m_axis_tlast == f_ml_q);
            end
            // No interleaving: inside a packet, the output stays with that packet's source.
            if (m_axis_tvalid && f_oidx != 3'd0) assert(msg == f_omsg);
            if (msg) begin
                assert(f_oidx <= 3'd3);
                assert(m_axis_tdata == f_msg_byte);
                assert(m_axis_tlast == (f_oidx == 3'd3));
                assert(!s_axis_tready);
            end else begin
                assert(m_axis_tdata == s_axis_tdata && m_axis_tlast == s_axis_tlast);
                assert(m_axis_tvalid == s_axis_tvalid && s_axis_tready == m_axis_tready);
            end
            assert(done_o == (msg && f_mhs && f_oidx == 3'd3));
            // Induction.
            assert(mid_q == (f_oidx != 3'd0 && !f_omsg));
            if (!msg_q) assert(idx_q == 2'd0);
            if (msg_q) assert({1'b0, idx_q} == f_oidx && (f_oidx == 3'd0 || f_omsg));
            if (!msg_q && f_oidx != 3'd0) assert(!f_omsg);
        end
    end

    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(done_o && f_oidx == 3'd3 && f_mv_q && !f_mr_q);   // a message stalled on its last byte
        cover(msg && f_oidx == 3'd0 && stall_q == 1'b0 && req_i && s_axis_tvalid); // message wins a boundary
        cover(f_done_q && f_mhs && !msg);                        // a stream byte right after it
    end
