// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Takes the event queue's entries (one per clock that had events: timer
// references r, timer finishes f, the command reply, a DIG_IO RFLX value,
// a heartbeat, and T after that clock) in order, and within an entry one
// item per clock: the timers by ascending pin, then the reply, then the
// heartbeat, which is the contract's order for events of one clock; the
// queue keeps the order of clocks. So the order of packets costs a queue,
// not an age matrix. The DIG_IO value goes before the entry's first timer
// whose device ID is above its own (RFLX strobes of one clock: lowest ID
// first).
//
// A DIG_IO RFLX value travels in its entry (ID and level), so it needs no
// slot and never stalls the input.
//
// A timer's bits in an entry: r alone is a reference, f alone a completion,
// both a timeout (bsd_timer_bank), so no timer keeps a timed-out flag.
// Items go through two registered stages. A: every timer item writes T into
// the timer's reference RAM (a finish follows its run's reference and reads
// it before its own write); a finish's result, T - reference (1 if that is 0;
// 0 for a timeout), is worked out from the reference the RAM read on the
// pick's clock. B: the result (a flop) is queued for the
// transmitter when HOST is set (order_*) and strobed on rflx_* when RFLX is
// set; the reply and heartbeat are queued, the DIG_IO value strobed. Never
// waits for the host link: the output queue has room for every packet that
// can be waiting (one per timer, the reply, the heartbeat), so RFLX strobes
// are never held back by it.
//
// A finish's HOST and RFLX bits are its run's (the timer's last start's): up
// to 16 timers bsd_timer_bank's flops (run_host_i, run_rflx_i); from
// MEM_TIMERS (17) on a word a timer in a one-port memory here, written from
// the start ports and read in stage A (see "the runs' HOST and RFLX bits"
// below, with why a write can wait and still lands first); hold_o then holds
// the parser while a start's write waits. From MEM_TIMERS on, stage A also
// reads a timer item's r and f bits and T from the queue's head, which is
// taken only after the entry's last item (see "the entry's r, f and T").
module bsd_drain #(
    parameter integer        NUM_PINS      = 5,
    parameter [NUM_PINS-1:0] TIMER_MASK    = 5'b11110,
    parameter integer        TIMER_ID_BASE = 10,
    // The number of timers (TIMER_MASK's ones, at least 1): timer t is the
    // t-th pin of TIMER_MASK.
    parameter integer        NT            = 4,
    // The DIG_IO values' device IDs lie in DIO_ID_LO..DIO_ID_HI (the top's
    // pin IDs): a timer whose ID is above them all never ranks before a value,
    // one not above the lowest always does, so their rank gates fold away
    // (GP 1.0: every timer ID is above every pin's, and the value's rank is
    // no gate on the pick's enable, the iCEBreaker top's critical path).
    parameter integer        DIO_ID_LO     = 0,
    parameter integer        DIO_ID_HI     = 63,
    // Above 16 timers the pick works in groups of this many (below; at least
    // 1); the proof sets 4, so that a few timers make several groups.
    parameter integer        PICK_GROUP    = 16,
    // From this many timers on, the runs' HOST and RFLX bits are a memory
    // here (below), not run_host_i/run_rflx_i. The proof lowers it to check
    // the memory form on a few timers.
    parameter integer        MEM_TIMERS    = 17
) (
    input  wire                       clk,
    input  wire                       rst,
    // the event queue's head
    input  wire                       ev_valid_i,
    input  wire [2*NT+25:0]           ev_data_i,    // {r, f, reply, dio, hb, dio ID, dio level, T}
    // The entry has timer events: r and f are valid and not both zero. (An
    // entry that skips the queue has none, and r and f are the queue's stale
    // word: the drain masks them in the gates that load rem_q, so the top
    // needs no gate per bit.) It is a bit of the queue's entry (bsd_timer_bank's
    // ev_any), so "a timer is left" is loaded without an OR over the timers.
    input  wire                       ev_timers_i,
    output wire                       ev_ready_o,
    output wire                       empty_o,      // no item left (a flop)
    // each timer's run's HOST and RFLX bits (bsd_timer_bank; below MEM_TIMERS only)
    input  wire [NT-1:0]              run_host_i,
    input  wire [NT-1:0]              run_rflx_i,
    // a timer's start (bsd_exec's stage 2: timer_go_o and its number, HOST and
    // RFLX bits; from MEM_TIMERS on only) and "a start's write is pending": no
    // start may come while it is set (the parser's hold, below)
    /* verilator lint_off UNUSEDSIGNAL */  // (below MEM_TIMERS)
    input  wire                       start_i,
    input  wire [5:0]                 start_idx_i,
    input  wire                       start_host_i,
    input  wire                       start_rflx_i,
    /* verilator lint_on UNUSEDSIGNAL */
    output wire                       hold_o,
    // to the transmitter's queue: {kind, timer, its device ID, result}
    output wire                       order_valid_o,
    output wire [29:0]                order_data_o,
    // RFLX
    // a timer without HOST is delivered: its strobe is given (with HOST the
    // packet's last byte, always later, frees the timer: bsd_timer_bank)
    output wire                       rflx_done_o,
    output wire [5:0]                 rflx_idx_o,
    output wire                       rflx_valid_o,
    output wire [5:0]                 rflx_id_o,
    output wire [15:0]                rflx_data_o
);
    localparam [1:0] KIND_TIMER = 2'd0;
    localparam [1:0] KIND_REPLY = 2'd1;
    localparam [1:0] KIND_HB    = 2'd2;
    // Timer t's device ID, TIMER_ID_BASE + its pin, in bits 6t..6t+5.
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [6*NT-1:0] id_table(input integer unused);
        integer p, t;
        begin
            id_table = {6*NT{1'b0}};
            t = 0;
            for (p = 0; p < NUM_PINS; p = p + 1) begin
                if (TIMER_MASK[p]) begin
                    id_table[6*t +: 6] = TIMER_ID_BASE[5:0] + p[5:0];
                    t = t + 1;
                end
            end
        end
    endfunction
    /* verilator coverage_on */
    localparam [6*NT-1:0] IDS = id_table(0);
    // Timer IDs that rise by one from timer 0's (timers on consecutive pins, GP 1.0's
    // and any full build's) are an addition, not a table.
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function contiguous(input integer unused);
        integer t;
        begin
            contiguous = 1'b1;
            for (t = 1; t < NT; t = t + 1)
                if (IDS[6*t +: 6] != IDS[6*(t-1) +: 6] + 6'd1) contiguous = 1'b0;
        end
    endfunction
    /* verilator coverage_on */
    localparam       CONTIG = contiguous(0);
    localparam [5:0] ID0    = IDS[5:0];
    // The memory forms (the runs' bits, the entry read from the queue's head,
    // "a timer is left" as an OR; below).
    localparam [0:0] MEM    = NT >= MEM_TIMERS;

    // ------------------------------------------------------------ the entry
    // The timers with an item left (rem_q, cleared as each is taken) and
    // their r and f bits (r_q, f_q: only loaded; stage A reads them as ent_r
    // and ent_f below MEM_TIMERS, and nothing reads them from it on).
    reg [NT-1:0]       rem_q, r_q, f_q;
    reg                rep_q, dio_q, hb_q;
    reg [5:0]          dio_id_q;
    reg                dio_val_q;
    reg [15:0]         t_q;

    // "A timer is left" as a flop (any_t_q), so the reply's and heartbeat's
    // picks and enables do not wait for an OR over the timers. From
    // MEM_TIMERS on it is that OR, and step()'s "two timers or more" is "a
    // timer now" (the entry's last item, when a timer, is followed by a clock
    // that finds none left): the exact test, a timer beside the pick, took 63
    // LUT4 at 64 timers (bsd_drain alone; uart64t 54 logic cells). An entry
    // whose last item is a timer then takes a clock more.
    reg                 any_t_q;
    wire                any_t  = MEM ? |rem_q : any_t_q;
    // Up to PICK_GROUP timers the pick is functions of the entry's flops
    // called in the clocked block on a clock with an item (not next), not
    // wires: a simulator then works it out only there, not on every clock
    // (synthesis: the same gates). Above, it is the wire low_grp (below).
    // v & ~(v - 1), not v & (~v + 1): the carry chain takes v itself, not an
    // inverter per bit (iCE40's carry has no inverted input). Up to 8 timers:
    // a priority chain, smaller still and a few steps in simulation (at 16
    // the carry chain is the smaller: core16t 1200 against 1216 LUT4). Above
    // PICK_GROUP (16), one carry chain per group of 16 timers, all from flops
    // side by side, and a group's pick counts only when every group below is
    // empty (an OR of their bits, beside the chains), so no chain is longer
    // than 16 bits: the 64-bit chain was uart64t's critical path (44 ns in
    // nextpnr). uart64t's static estimate (synth/depth.py): 41.2 -> 29.2 ns,
    // 3517 -> 3564 LUT4; with the OR as the chains' subtrahend instead of a
    // gate after them, 33.8 ns and 3509 LUT4; groups of 8, 34.0 ns.
    localparam integer GS = PICK_GROUP;
    localparam integer NP = GS * ((NT + GS - 1) / GS);
    // The groups' pick (NT > PICK_GROUP), of rem_q.
    function [NT-1:0] lowest_grp(input [NT-1:0] v);
        integer g;
        reg below;
        reg [NP-1:0] w;
        /* verilator lint_off UNUSEDSIGNAL */
        reg [NP-1:0] l;  // its bits above NT pad the last group
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            w         = {NP{1'b0}};
            w[NT-1:0] = v;
            below     = 1'b0;  // a timer in a group below
            for (g = 0; g < NP / GS; g = g + 1) begin
                l[GS*g +: GS] = w[GS*g +: GS] & ~(w[GS*g +: GS] - {{(GS-1){1'b0}}, 1'b1}) & {GS{!below}};
                below = below || |w[GS*g +: GS];
            end
            lowest_grp = l[NT-1:0];
        end
    endfunction
    // A wire, built only above PICK_GROUP timers and picked at the call
    // sites: smaller builds then elaborate lowest() alone, as before the
    // groups (with the groups' form in an untaken branch of lowest(), yosys
    // and ABC mapped core16t's same logic 7 to 16 LUT4 larger). A simulator
    // works it out when rem_q changes, on an item's clock.
    wire [NT-1:0] low_grp;
    generate
        if (NT > GS) begin : g_grp
            assign low_grp = lowest_grp(rem_q);
        end else begin : g_flat
            assign low_grp = {NT{1'b0}};  // never read
        end
    endgenerate
    // The pick up to PICK_GROUP timers.
    function [NT-1:0] lowest(input [NT-1:0] v);
        integer t;
        reg seen;
        begin
            if (NT <= 8) begin
                seen = 1'b0;
                for (t = 0; t < NT; t = t + 1) begin
                    lowest[t] = v[t] && !seen;
                    seen = seen || v[t];
                end
            end else begin
                lowest = v & ~(v - {{(NT-1){1'b0}}, 1'b1});
            end
        end
    endfunction
    // The index of a one-hot timer vector: an OR per index bit.
    function [5:0] index_of(input [NT-1:0] oh);
        integer t;
        begin
            index_of = 6'd0;
            for (t = 0; t < NT; t = t + 1)
                if (oh[t]) index_of = index_of | t[5:0];
        end
    endfunction
    // The DIG_IO value goes first when no waiting timer ranks before it (an ID
    // not above its own). ID >= a constant, for every timer's ID, from three
    // 8-way decodes of the value's ID (dio_id_q), each spread over the timers
    // by constant masks (the timers whose ID has those high or low bits): a
    // gate per timer with its rem bit after synthesis, no comparator and no
    // flop per timer, so the pick compares no IDs; a few word operations in
    // simulation.
    // The timers whose ID's bits [5:3] (hi = 1) or [2:0] (hi = 0) are v, for
    // v = 0..7 in NT-bit fields. Only localparam initializers call it.
    /* verilator coverage_off */
    function [8*NT-1:0] id_masks(input integer hi);
        integer t;
        reg [2:0] f;
        begin
            id_masks = {8*NT{1'b0}};
            for (t = 0; t < NT; t = t + 1) begin
                f = hi != 0 ? IDS[6*t+3 +: 3] : IDS[6*t +: 3];
                id_masks[NT * {29'd0, f} + t] = 1'b1;
            end
        end
    endfunction
    /* verilator coverage_on */
    localparam [8*NT-1:0] HI_MASKS = id_masks(1);
    localparam [8*NT-1:0] LO_MASKS = id_masks(0);
    // The timers that may rank before a value (ID not above DIO_ID_HI) and
    // those that always do (ID not above DIO_ID_LO).
    // Only localparam initializers call it.
    /* verilator coverage_off */
    function [NT-1:0] id_le(input integer bound);
        integer t;
        begin
            for (t = 0; t < NT; t = t + 1)
                id_le[t] = {26'd0, IDS[6*t +: 6]} <= bound;
        end
    endfunction
    /* verilator coverage_on */
    // From MEM_TIMERS on with consecutive timer IDs (the 64-timer core's),
    // the value is not ranked in the pick at all (no gate a timer: 91 LUT4 at
    // 64 timers, bsd_drain alone): the timers go first, and the value when
    // none is left or, by a hold (below), right before the first timer whose
    // ID is above its own, found in stage A by its index.
    localparam [0:0]    RANK_IDX  = MEM && CONTIG;
    localparam [NT-1:0] MAY_RANK  = RANK_IDX ? {NT{1'b0}} : id_le(DIO_ID_HI);
    localparam [NT-1:0] MUST_RANK = RANK_IDX ? {NT{1'b0}} : id_le(DIO_ID_LO);
    // The timers whose ID is not above id (an ID in DIO_ID_LO..DIO_ID_HI).
    function [NT-1:0] ranks_of(input [5:0] id);
        integer dv;
        reg [NT-1:0] hi_gt_t, hi_eq_t, lo_ge_t;
        begin
            hi_gt_t = {NT{1'b0}};
            hi_eq_t = {NT{1'b0}};
            lo_ge_t = {NT{1'b0}};
            for (dv = 0; dv < 8; dv = dv + 1) begin
                hi_gt_t = hi_gt_t | ({NT{id[5:3] > dv[2:0]}} & HI_MASKS[NT*dv +: NT]);
                hi_eq_t = hi_eq_t | ({NT{id[5:3] == dv[2:0]}} & HI_MASKS[NT*dv +: NT]);
                lo_ge_t = lo_ge_t | ({NT{id[2:0] >= dv[2:0]}} & LO_MASKS[NT*dv +: NT]);
            end
            ranks_of = (hi_gt_t | (hi_eq_t & lo_ge_t)) & MAY_RANK | MUST_RANK;
        end
    endfunction
    // A clock with an item (not next): {rem_q, any_t_q, dio_q, rep_q, hb_q}
    // after it, "no item left" after it (empty_q: the entry had one), and
    // stage A's {a_t_q, a_dio_q, a_rep_q, a_hb_q, a_k_q}. Items left after
    // this clock's: the entry has two or more; "two timers or more" is "a
    // timer beside the lowest" (the bits the pick leaves), which ends at
    // flops only (empty_q, any_t_q), so the pick's carry chain may feed it
    // (from MEM_TIMERS "a timer", above: any_t_q is then unread).
    function [NT+14:0] step(input [NT-1:0] r);
        reg [NT-1:0] low;
        reg rank_t, dio_first, two_t, take_t, more;
        begin
            low       = NT > GS ? low_grp : lowest(r);  // (r is rem_q, as in every call)
            rank_t    = |(r & ranks_of(dio_id_q)) | (RANK_IDX && any_t);
            dio_first = dio_q && !rank_t;
            two_t     = MEM ? any_t : |(r & ~low);
            take_t    = any_t && !dio_first;
            more      = two_t || (any_t && (dio_q || rep_q || hb_q)) ||
                        (dio_q && rep_q) || (dio_q && hb_q) || (rep_q && hb_q);
            step = {take_t ? r & ~low : r, take_t ? two_t : any_t,
                    dio_q && !dio_first, rep_q && (any_t || dio_q), hb_q && (any_t || dio_q || rep_q),
                    !more,
                    take_t, dio_first, !any_t && !dio_q && rep_q, !any_t && !dio_q && !rep_q && hb_q,
                    index_of(low)};
        end
    endfunction
`ifdef FORMAL
    wire [NT-1:0]       rem    = rem_q;
    wire [NT-1:0]       low    = NT > GS ? low_grp : lowest(rem);  // as in step()
    wire [NT-1:0]       ranks  = ranks_of(dio_id_q);
    wire [NT+3:0]       f_unused_next;
    wire                f_last, take_t, take_dio, take_rep, take_hb;
    wire [5:0]          k;
    assign {f_unused_next, f_last, take_t, take_dio, take_rep, take_hb, k} = step(rem);
    wire                more   = !f_last;
`endif
    // "No item left" as a flop of its own (not the OR of the entry's bits):
    // the next entry is loaded when it is set, the clock after the last item
    // (one idle clock between entries; from MEM_TIMERS a clock later after
    // an entry with timer events, below), so the queue's read enable and the
    // top's queue-skip test start at a flop, not at the pick (from
    // MEM_TIMERS the read enable also takes the head's timer bit). Items remain
    // after a clock that takes no entry when two or more were there (from
    // MEM_TIMERS also after a timer: step()'s two_t); after one that takes an
    // entry, the new entry's own.
    reg                 empty_q;
    wire                next      = empty_q;
    wire [NT-1:0]       ev_rf     = ev_data_i[2*NT+25 -: NT] | ev_data_i[NT+25 -: NT];
    wire                ev_t      = ev_valid_i && ev_timers_i;
    wire                ev_items  = ev_t || |ev_data_i[25:23];
    assign empty_o    = empty_q;

    // ------------------------------------------- the entry's r, f and T
    // Stage A reads a timer item's r and f bits and the entry's T. Up to
    // MEM_TIMERS timers they are copies (r_q, f_q, t_q), loaded with the
    // entry, which is taken from the queue as it loads. From MEM_TIMERS on
    // they are read from the queue's head itself (the event queue's RAM read
    // register), and synthesis drops the copies, which nothing reads: 2 NT +
    // 16 flops fewer, each an iCE40 logic cell of its own (a flop loaded
    // from a shared net; 144 at 64 timers). An entry with
    // timer events is then taken (ev_ready_o) only on the next clock with
    // next, when its last item has been through stage A; that clock loads
    // nothing (held_q), and the next entry loads on the clock after it. So
    // such an entry costs a clock more: its items, then two idle clocks
    // (three when its last item is a timer: any_t, above).
    // The head stays as it is until taken (AXI-Stream). An entry without
    // timer events (which stage A reads nothing of: the DIG_IO value has
    // copies of its own) is taken as it loads, as before, so that one may
    // come past the queue (the top's skip path).
    wire [NT-1:0] ent_r, ent_f;
    wire [15:0]   ent_t;
    wire          held;  // the entry on the queue's head was loaded: take it, load nothing
    generate
        if (MEM) begin : g_head
            reg held_q;
            always @(posedge clk) begin
                if (next) held_q <= !held_q && ev_t;
                if (rst) held_q <= 1'b0;
            end
            assign held       = held_q;
            assign ent_r      = ev_data_i[2*NT+25 -: NT];
            assign ent_f      = ev_data_i[NT+25 -: NT];
            assign ent_t      = ev_data_i[15:0];
            assign ev_ready_o = next && (held_q || !ev_t);
            wire unused_copies = ^{r_q, f_q, t_q};
        end else begin : g_copy
            assign held       = 1'b0;
            assign ent_r      = r_q;
            assign ent_f      = f_q;
            assign ent_t      = t_q;
            assign ev_ready_o = next;
        end
    endgenerate
    wire          load = next && !held;
    // The hold (RANK_IDX): stage A has a timer whose ID is above the waiting
    // DIG_IO value's (IDs rise with the index: one compare of flops). On
    // that clock the value goes to stage B instead, and nothing else moves:
    // no step, stage A and the reference it read kept, so
    // that the timer goes on the next clock. The timers before it were picked
    // in ascending order and each passed stage A with an ID not above the
    // value's, so the value goes after every one of those and before the
    // rest: the order of ranking in the pick, and on the same clocks (the
    // value's clock replaces the pick it would have taken). The top's range
    // check keeps ID0 + NT within the 6-bit IDs, so the 7-bit sum is the ID.
    wire          hold;
    generate
        if (RANK_IDX) begin : g_hold
            assign hold = a_t_q && dio_q && {1'b0, ID0} + {1'b0, a_k_q} > {1'b0, dio_id_q};
        end else begin : g_no_hold
            assign hold = 1'b0;
        end
    endgenerate

    // ---------------------------------------------------------- stage A, B
    reg        a_t_q, a_dio_q, a_rep_q, a_hb_q;
    reg [5:0]  a_k_q;
    // Stage A reads the entry's T and DIG_IO value from ent_t, dio_id_q and
    // dio_val_q: they hold the entry until the clock after its last item.
    reg        b_dio_val_q;
    reg        b_dio_q, b_rep_q, b_hb_q;
    // A pin vector widened to 64 bits, to be indexed by a 6-bit timer number.
    function [63:0] pad(input [NT-1:0] v);
        begin
            pad = 64'd0;
            pad[NT-1:0] = v;
        end
    endfunction
    // Stage A's timer's bit of a timer vector: the entry's r and f bits
    // (ent_r and ent_f still hold its entry: the next one loads on the clock
    // after its last item at the earliest) and the run's HOST and RFLX bits,
    // read by index, not by the pick's one-hot. Called only on a timer's
    // clock in stage A (a_t_q), so a simulator reads them only then.
    function at(input [NT-1:0] v);
        reg [63:0] w;
        begin
            w  = pad(v);
            at = w[a_k_q];
        end
    endfunction
    reg [5:0]  b_k_q;
    reg [15:0] b_res_q;  // the finish's result

    // The reference is read on the pick's clock, at the lowest waiting
    // timer's number (the one a timer item takes; a clock that takes another
    // item reads to no use), so that stage A has it and works the result out
    // into a flop: the subtraction and the "0 ticks" test then end at b_res_q,
    // not at the output queue's RAM write port behind the top's mux (the
    // iCEBreaker top's critical path), with no clock added. A reference is
    // written in stage A and a finish of the same timer is picked from a later
    // entry, two clocks after at the earliest (one idle clock between
    // entries): it reads the reference written. Every timer item writes its
    // T, not only a reference, so that the write enable is a flop (a_t_q),
    // not the entry's r and f bits looked up by a_k_q (the iCEBreaker top's
    // critical path on two seeds of five): a finish or a timeout has read
    // its reference on its pick's clock, before its own write, and the
    // timer's next run writes a reference of its own before it can finish
    // (a run starts only after the last one's result is delivered).
    (* no_rw_check *)  // a reference is read at the earliest a clock after it is written
    reg [15:0] ref_mem [0:63];
    reg [15:0] ref_rd_q;
    reg [NT+14:0] step_v;  // the pick's step, read only on its clock (below)
    always @(posedge clk) begin
        if (a_t_q) ref_mem[a_k_q] <= ent_t;
    end

    // T - reference as T + ~reference + 1: iCE40's carry chain takes its
    // operands uninverted, so ~reference is a LUT per bit anyway. "0 ticks"
    // (sent as 1) is tested on the operands, beside the carry chain, not
    // after it: bits 15:1 equal and the sum's bit 0 (its first, early off the
    // chain) 0. A timeout's 0 is b_res_q's synchronous reset (no gate a bit).
    // Called only in stage A with a timer (a_t_q), so a simulator works it out only then.
    function [15:0] elapsed(input [15:0] t, input [15:0] rv);
        reg [15:0] diff;
        begin
            diff    = t + ~rv + 16'd1;
            elapsed = {diff[15:1], diff[0] || t[15:1] == rv[15:1]};
        end
    endfunction

    reg        rflx_valid_q;
    reg [5:0]  rflx_id_q;
    reg [15:0] rflx_data_q;

    // Stage B's valid flags are decided in stage A and registered (b_ord_q,
    // b_rdone_q), so the transmitter's load and the timers' clears start at
    // a flop (in the memory form a LUT after it: the run's bits, g_hr); the
    // data come straight from stage B's flops (the output queue,
    // or the transmitter when that is empty, registers them).
    reg        b_ord_q, b_rdone_q, b_free_q;
    // (the memory form gates them at stage B with the run's bits: g_hr)
    wire       b_ord_w, b_rdone_w, b_free_w;
    assign order_valid_o = b_ord_w;
    assign order_data_o  = {b_rep_q ? KIND_REPLY : b_hb_q ? KIND_HB : KIND_TIMER, b_k_q, b_id_q, b_res_q};
    assign rflx_done_o   = b_free_w;
    assign rflx_idx_o    = b_k_q;
    assign rflx_valid_o  = rflx_valid_q;
    assign rflx_id_o     = rflx_id_q;
    assign rflx_data_o   = rflx_data_q;

    // The timer's device ID from stage A's index (not from the pick: the ID's
    // adder or table stays off the pick's carry chain), or the DIG_IO value's
    // ID: either item's ID in the same flops, so the RFLX strobe's ID needs no
    // mux of the two.
    reg  [5:0] b_id_q;
    wire [5:0] a_id = CONTIG ? ID0 + a_k_q : IDS[6*a_k_q +: 6];

    // ------------------------------------- the runs' HOST and RFLX bits
    // From MEM_TIMERS timers on, a word a timer in a memory of one port, not
    // a flop pair a timer in bsd_timer_bank (each flop a logic cell alone on
    // iCE40: 128 at 64 timers) and two 64:1 lookups by a_k_q here. On the
    // UP5K (BSD_SPRAM) it is an SPRAM, as bsd_cfg_regs's memory, since the
    // 64-timer core uses all the block RAMs it may have; one port is all an
    // SPRAM has. The memory reads on every clock with a timer in stage A
    // (a_t_q), at its index (a flop, not the pick: the pick's carry chains,
    // index and the route to the SPRAM at the die's edge were uart64t's
    // critical path, 33 ns), so the word is stage B's: stage A passes a
    // finish's flags as if it had both bits, and stage B gates them with
    // hr_rd_q (b_ord_w and the others: a LUT after the flops). A start's word
    // is written on its own clock when that has no read (!a_t_q), else it
    // waits in hp_* and is written on the first clock without; meanwhile
    // hold_o holds the parser, so no second start comes before it is written. A
    // packet handed over on clock v starts its timer on v+1 (bsd_exec's
    // stage 2) and hold_o shows from v+2 until the write's clock w. The
    // parser hands over no packet on a clock after one with pkt_valid or with
    // hold (its proof), and bsd_reply_slot holds on v+1 (pkt_valid_i), so the
    // next handover is on v+3 at the earliest and looks at the hold on the
    // clock before it: v+2 or later, where hold_o shows; so it comes on w+2
    // at the earliest and its start on w+3. (hold_o, a flop, shows only from
    // the clock after the start: enough, as handovers are 3 clocks apart.) So the
    // pending word is never overwritten, and no start comes on the clock that
    // writes it (an assumption of the proof). The write lands before any read that
    // matters: only a finish's item uses the bits, a finish of the started
    // timer is an event after the start, in an entry loaded after the start's
    // clock, and no load clock has a timer in stage A (no clock with next
    // has: a timer's step finds a timer left, so "no item left" waits for the
    // clock after it, and a load and reset clear stage A), so a
    // pending write is done by then (on the load's clock at the latest) and
    // the finish's stage A reads later. The timer's next start comes only after the finish is
    // delivered (after stage B), so the word stays until it is read. No
    // reset: every start writes its timer's word before its finish can read
    // it, and a core reset drops a pending write with the runs it belonged to.
    // The runs' bits stage A reads by a_k_q: in the memory form ones (the
    // flags are gated at stage B), so that the stage's RTL is the small
    // builds' as it was; the memory form is all in g_hr, so that
    // the small builds elaborate none of it (their netlist, and so GP 1.0's
    // mapping, unchanged: dead code in the shared clocked block moved core5's
    // by a few LUTs).
    // (run_host_i and run_rflx_i, or ones in the memory form: no toggles of their own)
    /* verilator coverage_off */
    wire [NT-1:0] run_host_w, run_rflx_w;
    /* verilator coverage_on */
    generate
        if (MEM) begin : g_hr
            /* verilator coverage_off */
`ifdef BSD_SPRAM
            (* ram_style = "huge" *)
`endif
            reg [1:0]  hr_mem [0:63];  // {HOST, RFLX} of each timer's last start
            /* verilator coverage_on */
            reg [1:0]  hr_rd_q;        // stage A's timer's word, for stage B
            reg        hp_q;           // a start's word waits to be written
            reg [5:0]  hp_k_q;
            reg [1:0]  hp_d_q;
            // One address for the read and the write, whose enables are
            // exclusive (a_t_q), so that the memory is one port as written.
            wire [5:0] hr_a   = a_t_q ? a_k_q : hp_q ? hp_k_q : start_idx_i;
            // The port apart from reset (an SPRAM has none).
            always @(posedge clk) begin
                if (a_t_q) begin
                    hr_rd_q <= hr_mem[hr_a];
                end else if (hp_q || start_i) begin
                    hr_mem[hr_a] <= hp_q ? hp_d_q : {start_host_i, start_rflx_i};
                end
            end
            always @(posedge clk) begin
                if (!a_t_q) hp_q <= 1'b0;
                if (a_t_q && start_i) begin
                    hp_q   <= 1'b1;
                    hp_k_q <= start_idx_i;
                    hp_d_q <= {start_host_i, start_rflx_i};
                end
                if (rst) hp_q <= 1'b0;
            end
            // Stage A passes a finish as if with both bits; stage B has them.
            assign run_host_w = {NT{1'b1}};
            assign run_rflx_w = {NT{1'b1}};
            assign b_ord_w    = b_ord_q && (b_rep_q || b_hb_q || hr_rd_q[1]);
            assign b_rdone_w  = b_rdone_q && hr_rd_q[0];
            assign b_free_w   = b_rdone_q && hr_rd_q[0] && !hr_rd_q[1];
            assign hold_o     = hp_q;
            wire unused_run = ^{run_host_i, run_rflx_i, b_free_q};
        end else begin : g_no_hr
            assign run_host_w = run_host_i;
            assign run_rflx_w = run_rflx_i;
            assign b_ord_w    = b_ord_q;
            assign b_rdone_w  = b_rdone_q;
            assign b_free_w   = b_free_q;
            assign hold_o     = 1'b0;
        end
    endgenerate

    always @(posedge clk) begin
        // Stage B's data are loaded only with an item of their kind (order_data_o
        // and rflx_idx_o are read only with their valid flags).
        if (a_t_q) begin
            b_ord_q   <= at(ent_f) && at(run_host_w);
            b_rdone_q <= at(ent_f) && at(run_rflx_w);
            b_free_q  <= at(ent_f) && at(run_rflx_w) && !at(run_host_w);
            b_res_q   <= elapsed(ent_t, ref_rd_q);
            if (at(ent_r)) b_res_q <= 16'd0;  // with a f bit: a timeout
            b_k_q     <= a_k_q;
            b_id_q    <= a_id;
        end else begin
            b_ord_q   <= a_rep_q || a_hb_q;
            b_rdone_q <= 1'b0;
            b_free_q  <= 1'b0;
        end
        if (a_dio_q) begin
            b_id_q      <= dio_id_q;
            b_dio_val_q <= dio_val_q;
        end
        b_dio_q  <= a_dio_q;
        // A hold (g_hold): the DIG_IO value goes to stage B now, stage A's timer
        // on the next clock. (An override after the shared assignments, not a
        // term in them: the small builds' RTL stays as it was, and with it
        // GP 1.0's mapping; the terms in them re-mapped the iCEBreaker top to
        // a worst seed of 52.9 MHz.)
        if (hold) begin
            b_ord_q     <= 1'b0;
            b_rdone_q   <= 1'b0;
            b_free_q    <= 1'b0;
            b_dio_q     <= 1'b1;
            b_id_q      <= dio_id_q;
            b_dio_val_q <= dio_val_q;
        end
        b_rep_q  <= a_rep_q;
        b_hb_q   <= a_hb_q;
        // (the step before the load, which excludes it: the step reads the entry's
        // flops before the load writes them, and a simulator keeps no copy of them)
        // The reference is read at the step's own index (step_v, a value of
        // this clock only, not a flop), so that the RAM's address and a_k_q
        // share one encoder.
        if (hold) dio_q <= 1'b0;
        if (!next && !hold) begin
            /* verilator lint_off BLKSEQ */
            step_v = step(rem_q);
            /* verilator lint_on BLKSEQ */
            {rem_q, any_t_q, dio_q, rep_q, hb_q, empty_q, a_t_q, a_dio_q, a_rep_q, a_hb_q, a_k_q} <= step_v;
            ref_rd_q <= ref_mem[step_v[5:0]];
        end
        if (load) begin
            // The entry: loaded the clock after the last one's last item (two
            // clocks after a held one), then one item a clock.
            rem_q     <= ev_t ? ev_rf : {NT{1'b0}};
            any_t_q   <= ev_t;
            rep_q     <= ev_valid_i && ev_data_i[25];
            dio_q     <= ev_valid_i && ev_data_i[24];
            hb_q      <= ev_valid_i && ev_data_i[23];
            empty_q   <= !(ev_valid_i && ev_items);
            // The entry's data only with an entry (they are read only with its
            // items), so that a simulator copies them only then, not on every
            // idle clock.
            if (ev_valid_i) begin
                r_q       <= ev_data_i[2*NT+25 -: NT];
                f_q       <= ev_data_i[NT+25 -: NT];
                dio_id_q  <= ev_data_i[22:17];
                dio_val_q <= ev_data_i[16];
                t_q       <= ev_data_i[15:0];
            end
        end
        if (next) {a_t_q, a_dio_q, a_rep_q, a_hb_q} <= 4'd0;  // (a_k_q is read only with a_t_q)
        rflx_valid_q  <= b_rdone_w || b_dio_q;
        if (b_rdone_w || b_dio_q) begin
            rflx_id_q     <= b_id_q;
            rflx_data_q   <= {b_res_q[15:1], b_dio_q ? b_dio_val_q : b_res_q[0]};
        end
        // A DIG_IO value's bits 15:1 are 0: the flops' synchronous reset (with
        // rst's), not a gate per bit.
        if (rst || b_dio_q) rflx_data_q[15:1] <= 15'd0;
        if (rst) begin
            rem_q         <= {NT{1'b0}};
            rep_q         <= 1'b0;
            dio_q         <= 1'b0;
            hb_q          <= 1'b0;
            any_t_q       <= 1'b0;
            empty_q       <= 1'b1;
            a_t_q         <= 1'b0;
            a_dio_q       <= 1'b0;
            a_rep_q       <= 1'b0;
            a_hb_q        <= 1'b0;
            b_dio_q       <= 1'b0;
            b_rep_q       <= 1'b0;
            b_hb_q        <= 1'b0;
            b_ord_q       <= 1'b0;
            b_rdone_q     <= 1'b0;
            b_free_q      <= 1'b0;
            rflx_valid_q  <= 1'b0;
            rflx_id_q     <= 6'd0;
            rflx_data_q[0] <= 1'b0;
        end
    end

`ifdef FORMAL
`include "bsd_drain_props.vh"
`endif
endmodule
`default_nettype wire
