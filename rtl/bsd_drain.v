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
// Items go through two registered stages. A: a reference writes T into the
// timer's reference RAM; a finish reads the reference. B: a finish's result
// is T - reference (1 if that is 0; 0 for a timeout); it is queued for the
// transmitter when HOST is set (order_*) and strobed on rflx_* when RFLX is
// set; the reply and heartbeat are queued, the DIG_IO value strobed. Never
// waits for the host link: the output queue has room for every packet that
// can be waiting (one per timer, the reply, the heartbeat), so RFLX strobes
// are never held back by it.
module bsd_drain #(
    parameter integer        NUM_PINS      = 5,
    parameter [NUM_PINS-1:0] TIMER_MASK    = 5'b11110,
    parameter integer        TIMER_ID_BASE = 10,
    // The number of timers (TIMER_MASK's ones, at least 1): timer t is the
    // t-th pin of TIMER_MASK.
    parameter integer        NT            = 4
) (
    input  wire                       clk,
    input  wire                       rst,
    // the event queue's head
    input  wire                       ev_valid_i,
    input  wire [2*NT+25:0]           ev_data_i,    // {r, f, reply, dio, hb, dio ID, dio level, T}
    output wire                       ev_ready_o,
    output wire                       empty_o,      // no item left (a flop)
    // the timers' delivery flags (bsd_timer_bank)
    input  wire [NT-1:0]              host_pend_i,
    input  wire [NT-1:0]              rflx_pend_i,
    // to the transmitter's queue: {kind, timer, its device ID, result}
    output wire                       order_valid_o,
    output wire [29:0]                order_data_o,
    // RFLX
    output wire                       rflx_done_o,  // a timer's strobe is given
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

    // The pins of bit b of an index, for the one-hot to index encoder (word
    // operations, not a loop over the pins).
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [NT-1:0] index_bit(input integer b);
        integer t;
        begin
            for (t = 0; t < NT; t = t + 1) index_bit[t] = ((t >> b) & 1) != 0;
        end
    endfunction
    /* verilator coverage_on */

    // A pin vector widened to 64 bits, to be indexed by a 6-bit timer number.
    function [63:0] pad(input [NT-1:0] v);
        begin
            pad = 64'd0;
            pad[NT-1:0] = v;
        end
    endfunction
    wire [63:0] host64 = pad(host_pend_i);
    wire [63:0] rflx64 = pad(rflx_pend_i);

    // ------------------------------------------------------------ the entry
    reg [NT-1:0]       r_q, f_q;
    reg                rep_q, dio_q, hb_q;
    reg [5:0]          dio_id_q;
    reg                dio_val_q;
    reg [15:0]         t_q;

    wire [NT-1:0]       rem    = r_q | f_q;
    wire                any_t  = |rem;
    wire [NT-1:0]       low    = rem & (~rem + {{(NT-1){1'b0}}, 1'b1});
    wire [5:0]          k;
    genvar g;
    generate
        for (g = 0; g < 6; g = g + 1) begin : g_enc
            localparam [NT-1:0] BITS = index_bit(g);
            assign k[g] = |(low & BITS);
        end
    endgenerate
    wire [5:0]          k_id      = CONTIG ? ID0 + k : IDS[6*k +: 6];
    // The DIG_IO value goes first when no waiting timer ranks before it (an ID
    // not above its own): the timers that do are worked out as the entry is
    // taken (before_q), so the pick compares no IDs.
    reg  [NT-1:0]       before_q;
    wire [NT-1:0]       before_d;
    // ID >= a constant, for every timer's ID, from three 8-way decodes of the
    // value's ID (a 3-input gate per timer, no comparator per timer).
    wire [5:0]          dio_id_in = ev_data_i[22:17];
    wire [7:0]          hi_gt, hi_eq, lo_ge;
    generate
        for (g = 0; g < 8; g = g + 1) begin : g_dec
            /* verilator lint_off UNSIGNED */
            assign hi_gt[g] = dio_id_in[5:3] > g;
            assign hi_eq[g] = dio_id_in[5:3] == g;
            assign lo_ge[g] = dio_id_in[2:0] >= g;
            /* verilator lint_on UNSIGNED */
        end
        for (g = 0; g < NT; g = g + 1) begin : g_before
            localparam [5:0] ID = IDS[6*g +: 6];
            assign before_d[g] = hi_gt[ID[5:3]] | (hi_eq[ID[5:3]] & lo_ge[ID[2:0]]);
        end
    endgenerate
    wire                dio_first = dio_q && !(|(rem & before_q));
    wire                take_t    = any_t && !dio_first;
    wire                take_dio  = dio_first;
    wire                take_rep  = !any_t && !dio_q && rep_q;
    wire                take_hb   = !any_t && !dio_q && !rep_q && hb_q;
    // Items left after this clock's: when none, the next entry is taken now
    // (an item every clock, entries back to back). A clock with an item takes
    // exactly one, so items are left when the entry has two or more, whichever
    // is picked: counted on the entry's bits, beside the pick, not after it.
    // "Two timers or more" by a tree of 4-bit groups (any, two or more), not
    // a carry chain, which keeps the queue's pop (ev_ready_o) short.
    function two_or_more(input [NT-1:0] v);
        integer lvl, i, j, c;
        reg [63:0] any, two, any_n, two_n;
        begin
            any = 64'd0;
            any[NT-1:0] = v;
            two = 64'd0;
            for (lvl = 0; lvl < 3; lvl = lvl + 1) begin
                any_n = 64'd0;
                two_n = 64'd0;
                for (i = 0; i < 16; i = i + 1) begin
                    for (j = 0; j < 4; j = j + 1) begin
                        two_n[i] = two_n[i] | two[4*i + j];
                        for (c = j + 1; c < 4; c = c + 1)
                            two_n[i] = two_n[i] | (any[4*i + j] & any[4*i + c]);
                        any_n[i] = any_n[i] | any[4*i + j];
                    end
                end
                any = any_n;
                two = two_n;
            end
            two_or_more = two[0];
        end
    endfunction
    wire                more      = two_or_more(rem) || (any_t && (dio_q || rep_q || hb_q)) ||
                                    (dio_q && rep_q) || (dio_q && hb_q) || (rep_q && hb_q);
    wire                next      = !more;

    assign ev_ready_o = next;
    // "No item left" as a flop of its own (not the OR of the entry's bits): it
    // gates the queue's write enable, whose full/empty logic then starts at a
    // flop. Items remain after a clock that takes no entry; after one that
    // does, the new entry's own.
    reg                 empty_q;
    wire                ev_items  = |ev_data_i[2*NT+25:23];
    assign empty_o    = empty_q;

    // ---------------------------------------------------------- stage A, B
    reg        a_t_q, a_r_q, a_dio_q, a_rep_q, a_hb_q;
    reg [5:0]  a_k_q;
    reg [5:0]  a_dio_id_q, b_dio_id_q;
    reg        a_dio_val_q, b_dio_val_q;
    reg [15:0] a_t16_q;
    reg        b_fin_q, b_dio_q, b_rep_q, b_hb_q;
    reg        a_f_q;
    reg        b_host_q, b_rflx_q, b_tmo_q;
    reg [5:0]  b_k_q;
    reg [15:0] b_t16_q;

    (* no_rw_check *)  // a reference is read at the earliest a clock after it is written
    reg [15:0] ref_mem [0:63];
    reg [15:0] ref_rd_q;
    always @(posedge clk) begin
        if (a_t_q && a_r_q && !a_f_q) ref_mem[a_k_q] <= a_t16_q;
        ref_rd_q <= ref_mem[a_k_q];
    end

    wire [15:0] diff   = b_t16_q - ref_rd_q;
    // "0 ticks" tested on the operands, beside the subtraction, not after it.
    wire [15:0] result = b_tmo_q ? 16'd0 : (b_t16_q == ref_rd_q ? 16'd1 : diff);

    reg        rflx_valid_q;
    reg [5:0]  rflx_id_q;
    reg [15:0] rflx_data_q;

    // Straight from stage B (the output queue, or the transmitter when that
    // is empty, registers it).
    assign order_valid_o = (b_fin_q && b_host_q) || b_rep_q || b_hb_q;
    assign order_data_o  = {b_rep_q ? KIND_REPLY : b_hb_q ? KIND_HB : KIND_TIMER, b_k_q, b_id_q, result};
    assign rflx_done_o   = b_fin_q && b_rflx_q;
    assign rflx_idx_o    = b_k_q;
    assign rflx_valid_o  = rflx_valid_q;
    assign rflx_id_o     = rflx_id_q;
    assign rflx_data_o   = rflx_data_q;

    reg  [5:0] a_id_q, b_id_q;

    always @(posedge clk) begin
        // The entry: loaded as the last one's last item goes, then one item a clock.
        if (next) begin
            r_q       <= ev_valid_i ? ev_data_i[2*NT+25 -: NT] : {NT{1'b0}};
            f_q       <= ev_valid_i ? ev_data_i[NT+25 -: NT] : {NT{1'b0}};
            rep_q     <= ev_valid_i && ev_data_i[25];
            dio_q     <= ev_valid_i && ev_data_i[24];
            hb_q      <= ev_valid_i && ev_data_i[23];
            dio_id_q  <= ev_data_i[22:17];
            before_q  <= before_d;
            dio_val_q <= ev_data_i[16];
            t_q       <= ev_data_i[15:0];
        end else begin
            if (take_t) begin
                r_q <= r_q & ~low;
                f_q <= f_q & ~low;
            end
            if (take_dio) dio_q <= 1'b0;
            if (take_rep) rep_q <= 1'b0;
            if (take_hb) hb_q <= 1'b0;
        end
        empty_q <= next && !(ev_valid_i && ev_items);
        a_t_q   <= take_t;
        a_r_q <= |(r_q & low);
        a_f_q <= |(f_q & low);
        a_dio_q <= take_dio;
        a_rep_q <= take_rep;
        a_hb_q  <= take_hb;
        a_dio_id_q  <= dio_id_q;
        a_dio_val_q <= dio_val_q;
        a_k_q   <= k;
        a_id_q  <= k_id;
        a_t16_q <= t_q;
        b_fin_q  <= a_t_q && a_f_q;
        b_dio_q  <= a_dio_q;
        b_rep_q  <= a_rep_q;
        b_hb_q   <= a_hb_q;
        b_host_q <= host64[a_k_q];
        b_rflx_q <= rflx64[a_k_q];
        b_tmo_q  <= a_r_q;  // with a_f_q: a timeout
        b_k_q    <= a_k_q;
        b_id_q   <= a_id_q;
        b_dio_id_q  <= a_dio_id_q;
        b_dio_val_q <= a_dio_val_q;
        b_t16_q  <= a_t16_q;
        rflx_valid_q  <= (b_fin_q && b_rflx_q) || b_dio_q;
        rflx_id_q     <= b_dio_q ? b_dio_id_q : b_id_q;
        rflx_data_q   <= b_dio_q ? {15'd0, b_dio_val_q} : result;
        if (rst) begin
            r_q           <= {NT{1'b0}};
            f_q           <= {NT{1'b0}};
            rep_q         <= 1'b0;
            dio_q         <= 1'b0;
            hb_q          <= 1'b0;
            empty_q       <= 1'b1;
            a_t_q         <= 1'b0;
            a_dio_q       <= 1'b0;
            a_rep_q       <= 1'b0;
            a_hb_q        <= 1'b0;
            b_fin_q       <= 1'b0;
            b_dio_q       <= 1'b0;
            b_rep_q       <= 1'b0;
            b_hb_q        <= 1'b0;
            rflx_valid_q  <= 1'b0;
            rflx_id_q     <= 6'd0;
            rflx_data_q   <= 16'd0;
        end
    end

`ifdef FORMAL
`include "bsd_drain_props.vh"
`endif
endmodule
`default_nettype wire
