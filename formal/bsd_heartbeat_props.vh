// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_heartbeat (included at the end of the module under `ifdef FORMAL).
// tick_i, answer_i and answer_down_i are free; done_i is assumed only while req_o is 1 (bsd_pkt_tx
// tells only a requesting source). A reference written from PROTOCOL.md §3 (cmdHB) and
// DESIGN.md decision 8 counts ticks: with HB_RATE != 0 a heartbeat falls due on the PERIOD-th
// tick (HB_RATE x HB_UNIT_TICKS) after reset or after the previous due one, never with
// HB_RATE = 0. A due heartbeat is queued (req_o rises on the next clock) unless the previous
// one is not yet sent (then it is skipped: no new request, no type toggle); the first queued
// one is UP (type 0), then DOWN, UP, ... alternately (type_o = {7'd0, DOWN}); req_o falls only
// the clock after done_i. link_up_o rises on an answer of the latest queued heartbeat's type
// and falls when a heartbeat falls due while the previous one is unanswered or unsent; 0 after
// reset. Asserted: req_o, type_o and link_up_o equal the reference's after every clock, the
// internal "due" equals the reference's due, and each output changes only as those rules
// allow. Induction: the tick counter equals the reference count (< PERIOD; with HB_RATE = 0
// it runs on and wraps at 2^W, harmless: nothing falls due), at_end_q exact.
// The cover and bmc tasks (define F_ANYSTATE) start from any state that meets these
// invariants, not from reset, so that they reach heartbeats without 16 000 ticks each (the bmc
// task gives a counterexample where the prove task's base case cannot reach one).
    reg          f_past_valid = 1'b0;
    reg          f_rst_q, f_due_q, f_done_q, f_answer_q, f_req_q, f_link_q;
    reg  [7:0]   f_type_q;
    reg  [W-1:0] f_cnt;        // ticks since reset or the last due heartbeat
    reg          f_queued;     // a heartbeat queued since reset
    reg          f_type;       // the latest queued heartbeat's type (1 = DOWN)
    reg          f_answered;   // it is answered
    reg          f_pending;    // it waits to be sent
    reg          f_link;
    wire         f_due    = (HB_RATE != 0) && tick_i && f_cnt == PERIOD - 1;
    wire         f_answer = answer_i && f_queued && answer_down_i == f_type;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q   <= rst;
        f_due_q   <= f_due;
        f_done_q  <= done_i;
        f_answer_q <= f_answer;
        f_req_q   <= req_o;
        f_link_q  <= link_up_o;
        f_type_q  <= type_o;
        if (tick_i) f_cnt <= f_due ? {W{1'b0}} : f_cnt + 1'b1;
        if (done_i) f_pending <= 1'b0;
        if (f_answer) begin
            f_answered <= 1'b1;
            f_link     <= 1'b1;
        end
        if (f_due) begin
            // Unanswered (an answer on this very clock counts) or not even sent: link down.
            if (!(f_answered || f_answer) || f_pending) f_link <= 1'b0;
            if (!f_pending) begin
                f_pending  <= 1'b1;
                f_type     <= f_queued ? !f_type : 1'b0;
                f_queued   <= 1'b1;
                f_answered <= 1'b0;
            end
        end
        if (rst) begin
            f_cnt      <= {W{1'b0}};
            f_queued   <= 1'b0;
            f_type     <= 1'b0;
            f_answered <= 1'b0;
            f_pending  <= 1'b0;
            f_link     <= 1'b0;
        end
    end

    wire f_inv = ticks_q == f_cnt && (HB_RATE == 0 || f_cnt <= PERIOD - 1) && at_end_q == (ticks_q == PERIOD - 1) &&
                 req_q == f_pending && down_q == f_type && queued_q == f_queued &&
                 answered_q == f_answered && link_up_q == f_link && (f_queued || !f_type) &&
                 (f_queued || !f_pending) && (f_queued || !f_link) && (HB_RATE != 0 || !f_queued);

    always @(*) begin
`ifdef F_ANYSTATE
        if (!f_past_valid) assume(!rst && f_inv);
`else
        if (!f_past_valid) assume(rst);
`endif
        if (done_i) assume(req_o);
        if (f_past_valid && !f_rst_q) begin
            assert(f_inv);
            assert(due == f_due);
            assert(req_o == f_pending);
            assert(type_o == {7'd0, f_type});
            assert(link_up_o == f_link);
            // Each output changes only as the rules allow.
            if (req_o && !f_req_q) assert(f_due_q);
            if (!req_o && f_req_q) assert(f_done_q);
            if (type_o != f_type_q) assert(req_o && !f_req_q);
            if (link_up_o && !f_link_q) assert(f_answer_q);
            if (!link_up_o && f_link_q) assert(f_due_q);
            if (HB_RATE == 0) assert(!req_o && !link_up_o);
        end
        if (f_past_valid && f_rst_q) assert(!req_o && !link_up_o && type_o == 8'd0);
    end

`ifdef F_ANYSTATE
    // Covers: a heartbeat sent; a DOWN queued after an UP and an UP after a DOWN; the link up
    // on an answer; the link down on an unanswered (sent) heartbeat; a heartbeat skipped (due
    // while the previous waits, the link up until then).
    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover(f_req_q && !req_o);
        cover(req_o && !f_req_q && type_o[0] && !f_type_q[0]);
        cover(req_o && !f_req_q && !type_o[0] && f_type_q[0]);
        cover(link_up_o && !f_link_q);
        cover(!link_up_o && f_link_q && !f_req_q);
        cover(f_due && req_o && link_up_o);
    end
`endif
