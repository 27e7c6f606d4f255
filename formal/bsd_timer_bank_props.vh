// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_timer_bank (included at the end of the module under `ifdef FORMAL).
// The neighbours are assumed as brainstem_dio has them: a start only of an idle timer
// (bsd_exec checks busy_o), at most one a clock; host_done_i only for a timer whose start
// asked for HOST and rflx_done_i only for one that asked for RFLX alone (bsd_drain: with
// both, the strobe always comes before the packet's last byte, which frees the timer), whose
// result is owed and whose measurement has ended, with an index below NUM_TIMERS. Levels,
// ticks, expire_i, modes: free.
// A reference written from PROTOCOL.md §4.2 and DESIGN.md decision 3 keeps, per timer, the
// HOST and RFLX bits of its last start and whether its result is owed until delivered.
// Asserted: busy_o is the measurement running or the result owed (busy until delivered,
// exactly); run_host_o and run_rflx_o are the last start's bits; a finish event comes
// exactly on the clock after a delivering measurement ends, and never otherwise; a
// reference event only after a start or while running; T counts ticks.
    localparam [NUM_TIMERS-1:0] F_ONE = {{(NUM_TIMERS-1){1'b0}}, 1'b1};
    reg                  f_past_valid = 1'b0;
    reg                  f_rst_q, f_tick_q;
    reg [NUM_TIMERS-1:0] f_host, f_rflx;           // the last start's bits (the reference)
    reg [NUM_TIMERS-1:0] f_owed, f_started;         // the result is owed; started since reset
    reg [NUM_TIMERS-1:0] f_run_q, f_start_q, f_deliver_q, f_expire_q, f_timed_out;
    reg [15:0]           f_t_q;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q      <= rst;
        f_tick_q     <= tick_i;
        f_run_q      <= run_q;
        f_start_q    <= start_i;
        f_deliver_q  <= pend_q;
        f_expire_q   <= expire_i;
        f_timed_out  <= (f_timed_out | (ev_r_q & ev_f_q)) & ~start_i;
        f_t_q        <= t_q;
        f_host <= (f_host & ~start_i) | (start_i & {NUM_TIMERS{host_i}});
        f_rflx <= (f_rflx & ~start_i) | (start_i & {NUM_TIMERS{rflx_i}});
        f_owed <= (f_owed & ~(host_done_i ? F_ONE << host_idx_i : NONE) & ~(rflx_done_i ? F_ONE << rflx_idx_i : NONE)) |
                  (start_i & {NUM_TIMERS{host_i || rflx_i}});
        f_started <= f_started | start_i;
        if (rst) begin
            f_owed <= NONE;
            f_started <= NONE;
            f_timed_out <= NONE;
        end
    end

    integer f_k;
    always @(*) begin
        if (!f_past_valid) assume(rst);
        assume((start_i & busy_o) == NONE);
        assume((start_i & (start_i - 1'b1)) == NONE);
        if (host_done_i) assume(host_idx_i < NUM_TIMERS && f_owed[host_idx_i] && f_host[host_idx_i] &&
                                !run_q[host_idx_i]);
        if (rflx_done_i) assume(rflx_idx_i < NUM_TIMERS && f_owed[rflx_idx_i] && f_rflx[rflx_idx_i] &&
                                !f_host[rflx_idx_i] && !run_q[rflx_idx_i]);
        if (host_done_i && rflx_done_i) assume(host_idx_i != rflx_idx_i);

        if (f_past_valid && !rst) begin
            assert(((run_host_o ^ f_host) & f_started) == NONE);
            assert(((run_rflx_o ^ f_rflx) & f_started) == NONE);
            assert(busy_o == (run_q | f_owed));
            assert(pend_q == f_owed);  // induction
            // induction: a timer owes a result only after a start with HOST or RFLX
            assert((f_owed & ~(f_host | f_rflx)) == NONE && (f_owed & ~f_started) == NONE);
            if (!f_rst_q) begin
                for (f_k = 0; f_k < NUM_TIMERS; f_k = f_k + 1) begin
                    // A finish event: exactly the clock after a delivering run ended.
                    assert(ev_f_q[f_k] == (f_run_q[f_k] && !run_q[f_k] && f_deliver_q[f_k]));
                    // A reference event: after a start or while running, never from an idle timer.
                    if (ev_r_q[f_k]) assert(f_start_q[f_k] || f_run_q[f_k]);
                    // A timeout (both bits): only on a tick its timer expires on.
                    if (ev_r_q[f_k] && ev_f_q[f_k]) assert(f_tick_q && f_expire_q[f_k]);
                end
                assert(t_q == f_t_q + {15'd0, f_tick_q});
            end
            assert(ev_any_o == |(ev_r_q | ev_f_q));
        end
    end

    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover(ev_f_q[0] && ev_r_q[0]);                        // a timeout delivered
        cover(ev_f_q == {NUM_TIMERS{1'b1}});                  // every timer finishing on one clock
        cover(f_start_q[1] && ev_r_q[1] && !f_run_q[1]);      // an edge-mode start's reference
        cover(busy_o == NONE && f_host[1] && f_timed_out[1]);  // delivered, free again
    end
