// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_timeout_wheel (included at the end of the module under `ifdef
// FORMAL). Assumed as brainstem_dio has it: at most one start a clock, only of a timer that
// is not running; run_i rises only the clock after that timer's start; ticks at least 3
// clocks apart (CLK_HZ >= 2 MHz); start_any_i and start_idx_i are start_i's strobe and number
// (bsd_exec). T (t_i) is free here, so the
// races hold whatever T does; that every timeout is caught in time rests on the scanner's
// lap (NUM_TIMERS clocks, doubled by starts) against the 60-tick window, and is simulated
// (tb/bsd_timeout_wheel, tb/brainstem_dio/test_scale.py).
// Asserted, the races of insert against completion and restart: every fresh in-window read
// writes its timer's bit, running or not, but a timer is marked inserted only if it is
// running, and never for a start read on the clock of a start of it or the clock before (the
// read may be the previous run's) or the clock after (stage 3); no bit is written then
// either, except on the start's own clock (the previous run's slot, never marked); the clock
// after a start the timer is neither inserted nor expiring (a wheel bit of an earlier run
// never counts); expire_o only names inserted timers; an insert never shares
// the write port with a slot's clearing (the scanner waits instead); an insert sets its
// timer's bit of the slot and no other, a clearing empties the slot; a timer is marked
// inserted exactly on the clock after its insert (without the mark its timeout never shows).
    localparam [NUM_TIMERS-1:0] ONE = 1;
    wire [NUM_TIMERS-1:0] f_wr_now  = insert ? (ONE << scan3_q) : NONE;  // the wheel bit written
    wire [NUM_TIMERS-1:0] f_ins_now = f_wr_now & run_i & ~ins_q;         // the timer marked now
    reg                  f_past_valid = 1'b0;
    reg                  f_rst_q, f_tick_q, f_tick2_q;
    reg [NUM_TIMERS-1:0] f_start_q, f_start2_q, f_start3_q;
    reg [NUM_TIMERS-1:0] f_run_q;
    reg [NUM_TIMERS-1:0] f_ins_q, f_insreg_q;  // last clock's insert, and its ins_q

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q    <= rst;
        f_tick_q   <= tick_i && !rst;
        f_tick2_q  <= f_tick_q && !rst;
        f_start_q  <= rst ? NONE : start_i;
        f_start2_q <= rst ? NONE : f_start_q;
        f_start3_q <= rst ? NONE : f_start2_q;
        f_run_q    <= run_i;
        f_ins_q    <= rst ? NONE : f_ins_now;
        f_insreg_q <= ins_q;
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        assume((start_i & (start_i - 1'b1)) == NONE);
        assume(start_any_i == (start_i != NONE));
        if (start_any_i) assume(start_i == (ONE << start_idx_i));
        assume((start_i & run_i) == NONE);
        if (f_past_valid) assume((run_i & ~f_run_q) == f_start_q);
        if (rst) assume(run_i == NONE);
        if (f_past_valid && (f_tick_q || f_tick2_q)) assume(!tick_i);

        if (f_past_valid && !rst && !f_rst_q) begin
            // A bit written on its timer's start clock is the previous run's (never marked).
            assert((f_wr_now & (f_start_q | f_start2_q | f_start3_q)) == NONE);
            assert((ins_q & ~f_insreg_q & ~f_run_q) == NONE);  // a mark only while running
            if (insert) assert(scan3_q < NUM_TIMERS);
            assert((f_start_q & (ins_q | expire_o)) == NONE);
            assert((expire_o & ~ins_q) == NONE);
            assert(!(insert && clear));
            assert((ins_q & ~f_insreg_q) == f_ins_q);
            // induction: the stage-2 flags follow the clocks they were taken on
            if (f_start_q != NONE || f_start2_q != NONE) assert(stale_q);
            if (f_start_q != NONE || f_start2_q != NONE || f_start3_q != NONE) assert(stale3_q);
            assert(tick2_q == f_tick2_q && tick1_q == f_tick_q);
        end
    end

    // The wheel's write (NUM_TIMERS <= 16 here: one RAM): an insert sets its timer's bit of the
    // slot and no other, a clearing empties the slot.
    reg                  f_wr_q;
    reg [5:0]            f_addr_q;
    reg [NUM_TIMERS-1:0] f_want_q;
    always @(posedge clk) begin
        f_wr_q   <= !rst && (insert || clear);
        f_addr_q <= w_addr;
        f_want_q <= clear ? NONE : g_wheel[0].wheel[w_addr] | (ONE << scan3_q);
    end
    always @(*) if (f_past_valid && f_wr_q) assert(g_wheel[0].wheel[f_addr_q] == f_want_q);

    always @(*) if (f_past_valid && !f_rst_q && !rst) begin
        cover(insert);
        cover(tick_i && (expire_o & run_i) != NONE);             // a timeout
        cover(f_start_q[0] && expire_q[0]);                       // restart after its slot was read
    end
