// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_tx (included at the end of the module under `ifdef FORMAL; the
// arbiter's own properties come along, with their assumption that a request waits at most
// 14 clocks). Sources (assumed): N <= 4, and from its request until its done_o a source
// keeps its request up and its N and data unchanged. Asserted: AXI-Stream (a stalled byte
// stays, with tlast); each packet is `A, N, d0..d(N-1)` of one source, whole, tlast exactly
// on byte N + 2, no interleaving; done_o pulses once, with the last byte's handshake, for
// the packet's source; with the sink ready, a packet started finishes in N + 2 clocks.
// Arbitration order: a reference of each request's age (clocks since it rose, as
// bsd_age_arb's own reference counts it; sources drop their request the clock after their
// done_o, assumed) ranks the sources oldest first, lowest index on ties. The packet going out
// ranks before every other waiting source, the staged one before every other waiting source
// but the current, and the arbiter's grant before every other candidate: packets leave in
// arbitration order (the source the arbiter granted, the oldest requester). And a source
// that has waited a clock always has a packet staged ahead of it or its own (no idle clock).
    reg          f_past_valid = 1'b0;
    reg          f_rst_q, f_mv_q, f_mr_q, f_ml_q;
    reg  [7:0]   f_md_q;
    reg  [K-1:0] f_req_q, f_done_q;
    reg  [3*K-1:0]  f_n_q;
    reg  [32*K-1:0] f_data_q;
    reg  [2:0]   f_idx;      // bytes of the current packet already taken
    reg  [3:0]   f_run;      // clocks since the packet's first byte was offered
    reg          f_stalled;  // the sink stalled it at least once
    reg          f_nv_q;
    reg  [K-1:0] f_ns_q;
    wire         f_hs = m_axis_tvalid && m_axis_tready;
    integer      f_s, f_a;  // one loop variable per block

    // The current source's packet, as it should go out.
    reg  [2:0]   f_n;
    reg  [31:0]  f_d;
    always @(*) begin
        f_n = 3'd0;
        f_d = 32'd0;
        for (f_s = 0; f_s < K; f_s = f_s + 1)
            if (cur_q[f_s]) begin
                f_n = f_n | n_i[3*f_s +: 3];
                f_d = f_d | data_i[32*f_s +: 32];
            end
    end
    // The job has no long source (LONG_SRC = -1), so a packet is at most 6 bytes and the
    // output register's low 32 bits (d4..d7 of a long packet) stay 0.
    wire [79:0] f_ref = {ADDR_OWN, 5'd0, f_n, f_d, 32'd0} << (8 * f_idx);

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata; f_ml_q <= m_axis_tlast;
        f_req_q <= req_i; f_done_q <= done_o; f_n_q <= n_i; f_data_q <= data_i;
        if (f_hs) f_idx <= m_axis_tlast ? 3'd0 : f_idx + 3'd1;
        f_nv_q <= next_valid_q; f_ns_q <= next_src_q;
        if (m_axis_tvalid && !(f_hs && m_axis_tlast)) begin
            if (f_run != 4'd15) f_run <= f_run + 4'd1;
            if (!m_axis_tready) f_stalled <= 1'b1;
        end else begin
            f_run     <= 4'd0;
            f_stalled <= 1'b0;
        end
        if (rst) begin
            f_stalled <= 1'b0;
            f_idx <= 3'd0;
            f_run <= 4'd0;
        end
    end

    always @(*) begin
        // cmdRESET's flush resets the sources with it, so the source rules above do not
        // hold across it; formal/brainstem_dio.sby's reset task proves it at the top.
        assume(!flush_i);
        for (f_a = 0; f_a < K; f_a = f_a + 1) begin
            assume(n_i[3*f_a +: 3] <= 3'd4);
            if (f_past_valid && !f_rst_q && f_req_q[f_a] && !f_done_q[f_a]) begin
                assume(req_i[f_a]);
                assume(n_i[3*f_a +: 3] == f_n_q[3*f_a +: 3]);
                assume(data_i[32*f_a +: 32] == f_data_q[32*f_a +: 32]);
            end
        end
        if (f_past_valid && !f_rst_q && !rst) begin
            if (f_mv_q && !f_mr_q) begin
                assert(m_axis_tvalid);
                assert(m_axis_tdata == f_md_q);
                assert(m_axis_tlast == f_ml_q);
            end
            if (m_axis_tvalid) begin
                // One source, its packet byte by byte, tlast on byte N + 2.
                assert(cur_q != {K{1'b0}} && (cur_q & (cur_q - 1'b1)) == {K{1'b0}});
                assert((cur_q & req_i) == cur_q);
                assert(m_axis_tdata == f_ref[79:72]);
                assert(m_axis_tlast == ({1'b0, f_idx} == f_n + 3'd1));
                assert(f_idx <= f_n + 3'd1);
                // Induction: the shift register holds the rest of the packet.
                assert(buf_q == f_ref);
                assert(left_q == {1'b0, f_n} + 4'd2 - {1'b0, f_idx});
                assert(last_q == (left_q == 3'd1));
            end else begin
                assert(cur_q == {K{1'b0}});
                assert(f_idx == 3'd0);
            end
            assert(done_o == ((f_hs && m_axis_tlast) ? cur_q : {K{1'b0}}));
            // The staged source is one-hot or none, requesting, and not the current one.
            assert(next_valid_q == (next_src_q != {K{1'b0}}));
            assert((next_src_q & (next_src_q - 1'b1)) == {K{1'b0}});
            assert((next_src_q & cur_q) == {K{1'b0}});
            assert((next_src_q & req_i) == next_src_q);
            assert((done_q & (cur_q | next_src_q)) == {K{1'b0}});
            // With the sink ready on every clock since its first byte was offered, a packet
            // moves a byte a clock, so it leaves whole in N + 2 clocks.
            if (m_axis_tvalid && !f_stalled) assert({1'b0, f_idx} == f_run);
            // A staged packet goes out right after the current one (or at once).
            if (f_nv_q && (!f_mv_q || (f_mr_q && f_ml_q))) begin
                assert(m_axis_tvalid && f_idx == 3'd0);
                assert(cur_q == f_ns_q);
            end
        end
    end

    // Arbitration order.
    reg  [K-1:0] f_treq_q;   // req_i of the previous clock (the arbiter's req_q)
    reg  [3:0]   f_tage [0:K-1];
    wire [K-1:0] f_born = req_i & ~f_treq_q;
    wire [K-1:0] f_cand = f_treq_q & ~(cur_q | next_src_q | done_q);
    integer      f_t, f_u, f_v;
    always @(posedge clk) begin
        f_treq_q <= rst ? {K{1'b0}} : req_i;
        for (f_t = 0; f_t < K; f_t = f_t + 1)
            if (f_born[f_t]) f_tage[f_t] <= 4'd0;
            else if (f_treq_q[f_t] && f_tage[f_t] != 4'd15) f_tage[f_t] <= f_tage[f_t] + 4'd1;
    end
    // Source j ranks before source i.
    function f_first(input integer j, input integer i);
        f_first = (f_tage[j] > f_tage[i]) || (f_tage[j] == f_tage[i] && j < i);
    endfunction
    always @(*) begin
        f_v = 0;
        for (f_u = 0; f_u < K; f_u = f_u + 1) begin
            if (f_treq_q[f_u]) assume(f_tage[f_u] != 4'd15);  // as bsd_age_arb's props
            if (f_past_valid && f_done_q[f_u]) assume(!req_i[f_u]);
        end
        if (f_past_valid && !f_rst_q && !rst) begin
            for (f_u = 0; f_u < K; f_u = f_u + 1)
                for (f_v = 0; f_v < K; f_v = f_v + 1)
                    if (f_u != f_v && f_treq_q[f_v] && req_i[f_v]) begin
                        if (cur_q[f_u]) assert(f_first(f_u, f_v));
                        if (next_src_q[f_u] && !cur_q[f_v]) assert(f_first(f_u, f_v));
                        if (gnt[f_u] && f_cand[f_v]) assert(f_first(f_u, f_v));
                    end
            // Work conserving: a source that has waited a clock, and is not the current one,
            // has a packet staged (its own or an older one's), so it follows the current
            // packet with no idle clock.
            for (f_u = 0; f_u < K; f_u = f_u + 1)
                if (f_treq_q[f_u] && req_i[f_u] && !cur_q[f_u] && f_tage[f_u] != 4'd0)
                    assert(next_valid_q);
        end
    end

    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(f_hs && m_axis_tlast && next_valid_q && next_src_q != cur_q);  // back to back, two sources
        cover(f_hs && m_axis_tlast && f_idx == 3'd5);         // a 6-byte packet
        cover(f_mv_q && !f_mr_q && f_idx == 3'd3);            // a stall mid-packet
    end
