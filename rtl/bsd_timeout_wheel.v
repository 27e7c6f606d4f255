// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Timeouts without a comparator per timer. A measurement times out on the
// tick that brings T (bsd_timer_bank's tick count) to T_start - 1, 65 535
// ticks after its start (T is 16 bits). T_start is kept in a block RAM per
// timer. A background scanner visits one timer per clock, and once a
// timer's timeout is 3..62 ticks away it sets the timer's bit in slot
// T_start mod 64 of a wheel (a block RAM of 64 slots, one bit per timer,
// written through a bit mask) and, if the timer is running, marks it
// inserted. After every tick the
// slot of the timers whose timeout is the next tick is read and cleared, so
// expire_o holds exactly those (masked by inserted) in time for it (ticks
// are at least 3 clocks apart). A lap of the scanner is NUM_TIMERS clocks (20
// ticks at 2 MHz and 64 timers), well inside the 60-tick window, so every
// timeout is seen in time.
//
// Races: a start clears the timer's inserted mark (a wheel bit of an earlier
// run then never counts), and a scan that may have read the start of a
// previous run (any start on the scan's read clock or the clock before: a
// lap then takes at most twice as long) neither writes nor marks. The wheel
// needs no clearing after reset: every slot is read and cleared within 64
// ticks, long before any timer can be marked (62 ticks before its timeout,
// 65 473 ticks after its start).
module bsd_timeout_wheel #(
    parameter integer NUM_TIMERS = 4
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                tick_i,
    input  wire [15:0]         t_i,          // bsd_timer_bank's T
    input  wire [NUM_TIMERS-1:0] start_i,      // the timer that starts now (one at most)
    // The start's strobe and number come from the executor, which has both at
    // hand: no OR or encoder over the timers here.
    input  wire                start_any_i,  // start_i is not zero
    input  wire [5:0]          start_idx_i,  // the number of start_i's timer
    input  wire [NUM_TIMERS-1:0] run_i,
    output wire [NUM_TIMERS-1:0] expire_o
);
    localparam [NUM_TIMERS-1:0] NONE  = {NUM_TIMERS{1'b0}};
    localparam [5:0]          LAST  = NUM_TIMERS[5:0] - 6'd1;  // 64 timers: 63
    // The scanner's count is masked to a timer number's bits (GP 1.0's 4
    // timers: 2): its bits above are then constant 0, and synthesis keeps no
    // flops or gates for them (the count wraps at LAST before it needs them).
    localparam integer        SW    = NUM_TIMERS > 1 ? $clog2(NUM_TIMERS) : 1;
    localparam [5:0]          SCAN_MASK = 6'h3F >> (6 - SW);

    // -------------------------------------------------------- start times
    (* no_rw_check *)  // a read of the address being written is never used (stale_q)
    reg [15:0] st_mem [0:63];
    reg        st_q;          // a start on the previous clock
    reg [5:0]  st_idx_q;
    always @(posedge clk) begin
        // T now includes the start clock's tick: T_start.
        if (st_q) st_mem[st_idx_q] <= t_i;
    end

    // --------------------------------------------------------------- scanner
    reg  [5:0]  scan_q;       // stage 1: the timer whose start is read
    reg  [5:0]  scan2_q;      // stage 2: its start is in st_rd_q
    reg         stale_q;      // stage 2: the start read may be an earlier run's
    reg  [15:0] st_rd_q;
    wire        advance;      // the scanner moves on (it stalls while its insert waits)
    // The timeout is at T = T_start - 1: 3..62 ticks away when T_start - T is 4..63.
    wire [15:0] ahead    = st_rd_q - t_i;
    // ahead[15:6] not zero (ahead at least 64) as the carry out of adding
    // 65 472: the carry chain ORs the 10 bits, not a tree of gates.
    wire [16:0] hi_nz    = {1'b0, ahead} + 17'h0FFC0;
    wire        in_win   = !hi_nz[16] && ahead[5:2] != 4'd0;
    wire        unused_ahead = ^{ahead[1:0], hi_nz[15:0]};
    // Stage 3: the window test registered (the 16-bit subtraction stays off
    // the write port); the timer's running bit only gates its mark (ins_q).
    reg  [5:0]  scan3_q;
    reg  [5:0]  slot3_q;      // T_start mod 64: the wheel slot
    reg         win3_q;
    reg         stale3_q;     // or a start on stage 2's clock
    reg  [NUM_TIMERS-1:0] ins_q;  // inserted into the wheel for the current run
    // Every fresh in-window read writes its timer's bit, running or not,
    // inserted or not: no 64:1 lookup of the timer's state on the write
    // enable. Only a running timer is marked (ins_q, one gate a timer below),
    // and expire_o counts only marked timers; an idle timer's bit is the slot
    // of its last start, read and cleared within 64 ticks, and a new run is
    // marked 65 473 ticks after its start at the earliest.
    wire        cand     = !stale3_q && win3_q;
    // The timer written now as a one-hot, the write folded into its block
    // decode, so that each timer's ins_q bit is one gate.
    wire [NUM_TIMERS-1:0] ins_bit;
    bsd_idx_onehot #(.N(NUM_TIMERS)) u_ins_bit (.en_i(insert), .idx_i(scan3_q), .onehot_o(ins_bit));

    always @(posedge clk) begin
        if (advance) st_rd_q <= st_mem[scan_q];
    end

    // ---------------------------------------------------------------- wheel
    // The slot read: the timers whose timeout is the next tick (with ins_q).
    // It is the RAMs' read registers and is used straight from them, until
    // the next read (a clock after the next tick): no copy per timer.
    wire [NUM_TIMERS-1:0] expire_q;
    reg                tick1_q;   // the clock after a tick: read the next slot
    reg                tick2_q;   // the clock after that: clear it
    reg [5:0]          slot_q;    // the slot read

    // A tick now makes T = t_i + 1: the next tick's timeouts (T = t_i + 2)
    // are of the timers started at t_i + 3, slot t_i + 3.
    wire [5:0]          next_slot = t_i[5:0] + 6'd3;
    // The write port: clearing the slot just read comes first; a candidate
    // that loses waits a clock (the scanner stalls): a lap that is a multiple
    // of the tick pattern's period (64 timers at 2 MHz: 16 clocks) would
    // otherwise meet the clearing clock at the same timers on every lap.
    // The stall and the write are decided from flops alone (a clearing clock
    // and a fresh in-window read in stage 3): still one stall a tick at most.
    wire                clear  = tick2_q;
    wire                insert = cand && !clear;
    assign              advance = !(clear && cand);
    wire [5:0]          w_addr = clear ? slot_q : slot3_q;
    wire                w_bit  = !clear;
    // The wheel as one RAM per 16 timers (a block RAM's width): an insert
    // writes only its timer's RAM (its write enable) through a bit mask that
    // is the insert's one-hot (ins_bit, which ins_q takes as well), every bit
    // for a clear: no second decoder of scan3_q for the mask. A write
    // clock of any RAM (w_any) is tested once, before each RAM's select, so a
    // simulator tests only that on the other clocks.
    wire                w_any  = clear || cand;
    genvar g;
    generate
        for (g = 0; g < (NUM_TIMERS + 15) / 16; g = g + 1) begin : g_wheel
            localparam integer GW = NUM_TIMERS - 16 * g < 16 ? NUM_TIMERS - 16 * g : 16;
            (* no_rw_check *)  // the slot read is never the one written (see in_win)
            reg [GW-1:0] wheel [0:63];
            reg [GW-1:0] rd_q;
            // With w_any: clear, or an insert into this RAM (insert is cand && !clear).
            /* verilator lint_off WIDTHEXPAND */
            wire         w_sel_g = clear || scan3_q[5:4] == g;
            /* verilator lint_on WIDTHEXPAND */
            // The masked write as a word write whose unmasked bits are the
            // slot's own (yosys turns that feedback into the RAM's bit
            // mask): a simulator then keeps one pending write, not one a bit.
            // A function called under the write enable, not an always @*:
            // a simulator builds the word only on a clearing or inserting clock.
            function [GW-1:0] w_word(input [GW-1:0] old);
                integer b;
                reg [GW-1:0] w_mask;
                begin
                    w_mask = {GW{clear}} | ins_bit[16 * g +: GW];
                    w_word = old;
                    for (b = 0; b < GW; b = b + 1)
                        if (w_mask[b]) w_word[b] = w_bit;
                end
            endfunction
            always @(posedge clk) begin
                if (w_any) begin
                    if (w_sel_g) wheel[w_addr] <= w_word(wheel[w_addr]);
                end
                if (tick1_q) rd_q <= wheel[slot_q];
            end
            assign expire_q[16 * g +: GW] = rd_q;
        end
    endgenerate

    // A start after the slot was read drops the timer's mark (a new run). A
    // bit left in a slot by an earlier run or an idle timer never meets a new
    // mark: a slot is read and cleared within 64 ticks, a run is marked 65 473
    // ticks after its start at the earliest; and the slot read is never the
    // one written.
    assign expire_o = expire_q & ins_q;

    always @(posedge clk) begin
        st_q     <= start_any_i;
        st_idx_q <= start_idx_i;
        if (advance) begin
            // (from the pipeline's end back: each flop is read before it is written)
            scan3_q  <= scan2_q;
            scan2_q  <= scan_q;
            scan_q   <= scan_q == LAST ? 6'd0 : (scan_q + 6'd1) & SCAN_MASK;
            slot3_q  <= st_rd_q[5:0];
            win3_q   <= in_win;
        end
        // The start read now may be a previous run's when a new one is
        // written now (st_q) or next clock (start_any_i), or (stage 3) on the
        // clock after. A stall keeps the candidates: they stay stale if they were.
        stale3_q <= advance ? (stale_q || start_any_i) : (stale3_q || start_any_i);
        stale_q  <= st_q || start_any_i || (!advance && stale_q);
        // The insert's decoder only on an insert's clock (ins_bit is zero on the others), so
        // that a simulator works it out only then.
        ins_q    <= ((insert ? ins_q | (ins_bit & run_i) : ins_q) & ~start_i);
        tick1_q  <= tick_i;
        tick2_q  <= tick1_q;
        if (tick_i) slot_q <= next_slot;
        if (rst) begin
            st_q        <= 1'b0;
            scan_q      <= 6'd0;
            scan2_q     <= 6'd0;
            stale_q     <= 1'b1;
            stale3_q    <= 1'b1;
            win3_q      <= 1'b0;
            scan3_q     <= 6'd0;
            ins_q       <= NONE;
            tick1_q     <= 1'b0;
            tick2_q     <= 1'b0;
            slot_q      <= 6'd3;
        end
    end

`ifdef FORMAL
`include "bsd_timeout_wheel_props.vh"
`endif
endmodule
`default_nettype wire
