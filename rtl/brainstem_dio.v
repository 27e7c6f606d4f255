// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// brainstem_dio: the digital I/O subsystem of an Acroname BrainStem 1.0
// module (GP 1.0 and kin), driven by its binary command packets over a
// byte stream. The contract is PROTOCOL.md; docs/DESIGN.md has the block
// split, latencies and the decisions where the contract is silent.
module brainstem_dio #(
    parameter integer               CLK_HZ        = 48_000_000,
    parameter integer               MODULE_ADDR   = 2,
    parameter integer               NUM_PINS      = 5,
    parameter [NUM_PINS-1:0]        TIMER_MASK    = 5'b11110,
    parameter [NUM_PINS-1:0]        FIXED_MASK    = 0,
    parameter [8*NUM_PINS-1:0]      FIXED_CFG     = 0,
    parameter integer               PIN_ID_BASE   = 5,
    parameter integer               TIMER_ID_BASE = 10,
    // Names the raw_trans bits (raw input TRANS_ID_BASE + p) in transcripts
    // and docs only; the contract gives it no effect at the ports (only the
    // parameter checks below read it).
    parameter integer               TRANS_ID_BASE = 15,
    parameter integer               POLL_HZ       = 10_000,
    parameter integer               RX_TIMEOUT_US = 25_600,
    parameter integer               HB_RATE       = 0
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [7:0]          s_axis_tdata,
    input  wire                s_axis_tvalid,
    output wire                s_axis_tready,
    output wire [7:0]          m_axis_tdata,
    output wire                m_axis_tvalid,
    input  wire                m_axis_tready,
    output wire                m_axis_tlast,
    input  wire [NUM_PINS-1:0] pin_i,
    output wire [NUM_PINS-1:0] pin_o,
    output wire [NUM_PINS-1:0] pin_oe,
    output wire [NUM_PINS-1:0] raw_trans,
    output wire                rflx_valid,
    output wire [5:0]          rflx_id,
    output wire [15:0]         rflx_data,
    output wire                link_up
);
    `include "bsd_protocol.vh"

    // Timers are numbered 0..NT-1 in the order of their pins: the timer
    // blocks work on vectors of timers, so pins without one cost nothing
    // there. (With no timer at all one timer is built and never started.)
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer count_timers(input integer unused);
        integer q;
        begin
            count_timers = 0;
            for (q = 0; q < NUM_PINS; q = q + 1)
                if (TIMER_MASK[q]) count_timers = count_timers + 1;
        end
    endfunction
    /* verilator coverage_on */
    // The pin of timer t (t < count_timers).
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer pin_of_timer(input integer t);
        integer q, n;
        begin
            pin_of_timer = 0;
            n = 0;
            for (q = 0; q < NUM_PINS; q = q + 1) begin
                if (TIMER_MASK[q]) begin
                    if (n == t) pin_of_timer = q;
                    n = n + 1;
                end
            end
        end
    endfunction
    /* verilator coverage_on */
    // The number of timers on pins below q.
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer count_below(input integer q);
        integer r;
        begin
            count_below = 0;
            for (r = 0; r < q; r = r + 1)
                if (TIMER_MASK[r]) count_below = count_below + 1;
        end
    endfunction
    /* verilator coverage_on */
    localparam integer TIMERS = count_timers(0);
    localparam integer NT     = TIMERS == 0 ? 1 : TIMERS;
    // From this many pins on, bsd_cfg_regs keeps ENA, TSTATE and TMODE in a
    // memory, read with each packet: the timers then take the start's TMODE
    // and TSTATE from that read. From this many timers on, bsd_drain keeps
    // the runs' HOST and RFLX bits in a memory and reads an entry's timer
    // events from the event queue's head. One threshold for both blocks (the
    // 64-pin, 64-timer build's area; below it the flops are the smaller).
    localparam integer MEM_FROM = 17;
    // Where a timer number or a device ID comes out of a queue (block RAM,
    // whose bits synthesis cannot see through) or a mux, the bits that no
    // such number or ID of this build can have are given as the constants
    // they are, so that synthesis drops their logic downstream (few-pin
    // builds; with 64 pins every bit can vary and the masks are all ones).
    // The bits a timer number has (0 with one timer).
    localparam integer TNB    = $clog2(NT);
    localparam [5:0]   TIDX_MASK = 6'h3F >> (6 - TNB);
    // The bits that are 1 in the device ID base + p of some pin p in mask
    // (all 0), or of every such pin (all 1).
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [5:0] id_bits(input [5:0] base, input [NUM_PINS-1:0] mask, input all);
        integer q;
        reg [5:0] id;
        begin
            id_bits = all ? 6'h3F : 6'h00;
            for (q = 0; q < NUM_PINS; q = q + 1) begin
                id = base + q[5:0];
                if (mask[q]) id_bits = all ? id_bits & id : id_bits | id;
            end
        end
    endfunction
    /* verilator coverage_on */
    localparam [5:0]   TID_ANY = id_bits(TIMER_ID_BASE[5:0], TIMER_MASK, 1'b0);
    localparam [5:0]   TID_ALL = id_bits(TIMER_ID_BASE[5:0], TIMER_MASK, 1'b1);
    localparam [5:0]   PID_ANY = id_bits(PIN_ID_BASE[5:0], {NUM_PINS{1'b1}}, 1'b0);
    localparam [5:0]   PID_ALL = id_bits(PIN_ID_BASE[5:0], {NUM_PINS{1'b1}}, 1'b1);

    // An event queue entry: {timer events at all, timer references, timer
    // finishes, reply, DIG_IO RFLX value, heartbeat, the DIG_IO value's ID and
    // level, T}. The first bit (bsd_timer_bank's ev_any) spares the drain an
    // OR over the timers' bits; the drain takes the rest (DW bits).
    localparam integer DW = 2 * NT + 26;
    localparam integer EW = DW + 1;

    // ---------------------------------------------------------------- checks
    // One check and one message per rule of the contract (PROTOCOL.md §1,
    // README), each naming the parameter and its value. $fatal in an initial
    // block stops the simulation at time 0 with a non-zero exit, on Icarus 11
    // and on Verilator 5; Yosys defines SYNTHESIS and never sees the checks.
    // The widths of TIMER_MASK, FIXED_MASK and FIXED_CFG are their declared
    // ranges: the language cuts a wider value to them before any check could
    // see it (a Verilator build rejects such a value, WIDTHTRUNC).
`ifndef SYNTHESIS
    // The highest pin with a timer, -1 if none. (A Verilog-2005 function needs
    // an argument, hence the unused one.)
    // Only localparam initializers call it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer highest_timer_pin(input integer unused);
        integer q;
        begin
            highest_timer_pin = -1;
            for (q = 0; q < NUM_PINS; q = q + 1)
                if (TIMER_MASK[q]) highest_timer_pin = q;
        end
    endfunction
    /* verilator coverage_on */

    localparam integer TOP_TIMER = highest_timer_pin(0);

    initial begin
        if (CLK_HZ < 2_000_000)
            $fatal(1, "brainstem_dio: CLK_HZ = %0d must be at least 2000000", CLK_HZ);
        if (MODULE_ADDR < 2 || MODULE_ADDR > 254 || MODULE_ADDR % 2 != 0)
            $fatal(1, "brainstem_dio: MODULE_ADDR = %0d must be even and in 2..254", MODULE_ADDR);
        if (NUM_PINS < 1 || NUM_PINS > 64)
            $fatal(1, "brainstem_dio: NUM_PINS = %0d must be in 1..64", NUM_PINS);
        // Device IDs are 6 bits: every pin's level ID, every timer pin's ID,
        // every pin's raw transition ID.
        if (PIN_ID_BASE < 0 || PIN_ID_BASE + NUM_PINS - 1 > 63)
            $fatal(1, "brainstem_dio: PIN_ID_BASE = %0d gives pin IDs up to PIN_ID_BASE + NUM_PINS - 1 = %0d, must be in 0..63",
                   PIN_ID_BASE, PIN_ID_BASE + NUM_PINS - 1);
        if (TOP_TIMER >= 0 && (TIMER_ID_BASE < 0 || TIMER_ID_BASE + TOP_TIMER > 63))
            $fatal(1, "brainstem_dio: TIMER_ID_BASE = %0d gives timer IDs up to TIMER_ID_BASE + %0d (highest timer pin) = %0d, must be in 0..63",
                   TIMER_ID_BASE, TOP_TIMER, TIMER_ID_BASE + TOP_TIMER);
        if (TRANS_ID_BASE < 0 || TRANS_ID_BASE + NUM_PINS - 1 > 63)
            $fatal(1, "brainstem_dio: TRANS_ID_BASE = %0d gives raw input IDs up to TRANS_ID_BASE + NUM_PINS - 1 = %0d, must be in 0..63",
                   TRANS_ID_BASE, TRANS_ID_BASE + NUM_PINS - 1);
        if (POLL_HZ < 0 || POLL_HZ > CLK_HZ)
            $fatal(1, "brainstem_dio: POLL_HZ = %0d must be in 0..CLK_HZ (%0d)", POLL_HZ, CLK_HZ);
        if (RX_TIMEOUT_US < 0)
            $fatal(1, "brainstem_dio: RX_TIMEOUT_US = %0d must not be negative", RX_TIMEOUT_US);
        if (HB_RATE < 0 || HB_RATE > 100_000)
            $fatal(1, "brainstem_dio: HB_RATE = %0d must be in 0..100000", HB_RATE);
    end
`endif

    // ------------------------------------------------------------ cmdRESET
    // The executor's cmdRESET strobe resets every block as rst does, one clock
    // later, except two: the parser, which has taken no byte after the packet
    // (hold below) and so already waits for an address, and keeps the bytes
    // that come after it for after the reset; and the transmitter, which
    // finishes a packet already partly sent (bsd_pkt_tx, flush_i).
    wire soft_reset;
    reg  soft_rst_q;
    always @(posedge clk) begin
        soft_rst_q <= soft_reset;
        if (rst) soft_rst_q <= 1'b0;
    end
    wire core_rst = rst || soft_rst_q;

    // ------------------------------------------------------ time and inputs
    wire tick;
    wire poll;
    wire [NUM_PINS-1:0] level;

    bsd_tick_gen #(.CLK_HZ(CLK_HZ), .RATE_HZ(TICK_HZ)) u_tick (
        .clk(clk), .rst(core_rst), .tick_o(tick)
    );

    bsd_tick_gen #(.CLK_HZ(CLK_HZ), .RATE_HZ(POLL_HZ)) u_poll (
        .clk(clk), .rst(core_rst), .tick_o(poll)
    );

    bsd_sync #(.WIDTH(NUM_PINS)) u_sync (
        .clk(clk), .d_i(pin_i), .q_o(level)
    );

    // Arms the latches of fixed ENA pins two clocks after reset, once the
    // synchronizer holds real pad levels: they are armed from power-up. A free
    // pin comes out of reset with ENA = 0, and whatever sets its ENA re-arms
    // it, so arming it here could never show; leaving it out leaves its latch
    // a gate less.
    // Only a localparam initializer calls it: it runs while elaborating, never in simulation.
    /* verilator coverage_off */
    function [NUM_PINS-1:0] fixed_ena(input integer unused);
        integer q;
        begin
            for (q = 0; q < NUM_PINS; q = q + 1)
                fixed_ena[q] = FIXED_MASK[q] && FIXED_CFG[8*q + 1];
        end
    endfunction
    /* verilator coverage_on */
    localparam [NUM_PINS-1:0] FIXED_ENA = fixed_ena(0);
    reg [1:0] init_q;
    always @(posedge clk) begin
        init_q <= {init_q[0], 1'b0};
        if (core_rst) init_q <= 2'b11;
    end
    wire init_arm = |init_q;

    // -------------------------------------------------------------- parsing
    // The clock of the reset itself holds too (bsd_reply_slot's soft_reset_i):
    // a packet handed over then would meet the reply slot as the reset fills
    // it with the power-up message.
    wire       pkt_hold;
    // From 17 pins on, bsd_cfg_regs clears its memory after reset (no packet
    // meanwhile); from 17 timers on, bsd_drain's write of a start's HOST and
    // RFLX bits may be pending (0 below: the runs' bits are bsd_timer_bank's flops).
    wire       cfg_busy;
    wire       drain_hold;
    wire       pkt_valid;
    wire [1:0] pkt_kind;
    wire [3:0] pkt_n;
    wire [7:0] pkt_d0, pkt_d1, pkt_d2;
    wire [NUM_PINS-1:0] pkt_sel;
    wire [7:0] pkt_cmd;
    wire [39:0] pkt_tail;

    bsd_parser #(.MODULE_ADDR(MODULE_ADDR), .RX_TIMEOUT_US(RX_TIMEOUT_US), .NUM_PINS(NUM_PINS)) u_parser (
        .clk           (clk),
        .rst           (rst),
        .tick_i        (tick),
        .hold_i        (pkt_hold || cfg_busy || drain_hold),
        .s_axis_tdata  (s_axis_tdata),
        .s_axis_tvalid (s_axis_tvalid),
        .s_axis_tready (s_axis_tready),
        .pkt_valid_o   (pkt_valid),
        .pkt_kind_o    (pkt_kind),
        .pkt_n_o       (pkt_n),
        .pkt_d0_o      (pkt_d0),
        .pkt_cmd_o     (pkt_cmd),
        .pkt_d1_o      (pkt_d1),
        .pkt_sel_o     (pkt_sel),
        .pkt_d2_o      (pkt_d2),
        .pkt_tail_o    (pkt_tail)
    );

    // ------------------------------------------------------------ execution
    wire [5*NUM_PINS-1:0] cfg;
    wire [3:0]            cfg_rd;   // the memory's read of d1's pin (from MEM_FROM pins on)
    wire [NUM_PINS-1:0]   out_latch;
    wire [NUM_PINS-1:0]   pin_watch;
    wire [NUM_PINS-1:0]   timer_busy;
    wire                  cfg_we, out_we;
    wire [NUM_PINS-1:0]   wr_pin_sel;
    wire [4:0]            cfg_wdata;
    wire                  out_wdata;
    wire [NUM_PINS-1:0]   rearm;
    wire [NUM_PINS-1:0]   timer_start;
    wire                  timer_go;
    wire [5:0]            timer_idx;
    wire                  timer_host, timer_rflx;
    wire                  hb_answer;
    wire                  hb_answer_down;
    wire                  s2_valid;
    wire                  s2_reply;
    wire [3:0]            s2_reply_n;
    wire [31:0]           s2_reply_data;
    wire [31:0]           s2_reply_tail;
    wire                  s2_dio_rflx;
    wire [5:0]            s2_dio_id;
    wire                  s2_dio_val;

    bsd_exec #(
        .NUM_PINS    (NUM_PINS),
        .TIMER_MASK  (TIMER_MASK),
        .FIXED_MASK  (FIXED_MASK),
        .PIN_ID_BASE (PIN_ID_BASE),
        .CFG_MEM     (NUM_PINS >= MEM_FROM)
    ) u_exec (
        .clk             (clk),
        .rst             (core_rst),
        .pkt_valid_i     (pkt_valid),
        .pkt_kind_i      (pkt_kind),
        .pkt_n_i         (pkt_n),
        .pkt_cmd_i       (pkt_cmd),
        .pkt_d1_i        (pkt_d1),
        .pkt_sel_i       (pkt_sel),
        .pkt_d2_i        (pkt_d2),
        .pkt_tail_i      (pkt_tail),
        .cfg_i           (cfg),
        .cfg_rd_i        (cfg_rd),
        .level_i         (level),
        .timer_busy_i    (timer_busy),
        .cfg_we_o        (cfg_we),
        .out_we_o        (out_we),
        .pin_sel_o       (wr_pin_sel),
        .cfg_wdata_o     (cfg_wdata),
        .out_wdata_o     (out_wdata),
        .rearm_o         (rearm),
        .timer_start_o   (timer_start),
        .timer_go_o      (timer_go),
        .timer_idx_o     (timer_idx),
        .timer_host_o    (timer_host),
        .timer_rflx_o    (timer_rflx),
        .hb_answer_o     (hb_answer),
        .hb_answer_down_o(hb_answer_down),
        .soft_reset_o    (soft_reset),
        .s2_valid_o      (s2_valid),
        .reply_o         (s2_reply),
        .reply_n_o       (s2_reply_n),
        .reply_data_o    (s2_reply_data),
        .reply_tail_o    (s2_reply_tail),
        .dio_rflx_o      (s2_dio_rflx),
        .dio_id_o        (s2_dio_id),
        .dio_val_o       (s2_dio_val)
    );

    // The waiting reply and DIG_IO RFLX value; the parser holds a packet that
    // may need either slot while it is full or about to be filled.
    wire                  rep_req, rep_done;
    wire [3:0]            rep_n;
    wire [31:0]           rep_data;
    wire [31:0]           rep_tail;
    wire                  rep_new;
    wire                  dio_rflx_val, dio_rflx_new;
    wire [5:0]            dio_rflx_id;

    // The transmitter's swap (bsd_pkt_tx, declared here for the slot).
    wire                  tx_swap;

    bsd_reply_slot u_slot (
        .clk          (clk),
        .rst          (core_rst),
        .swap_i       (tx_swap),
        .pkt_valid_i  (pkt_valid),
        .soft_reset_i (soft_reset),
        .s2_valid_i   (s2_valid),
        .reply_i      (s2_reply),
        .reply_n_i    (s2_reply_n),
        .reply_data_i (s2_reply_data),
        .reply_tail_i (s2_reply_tail),
        .dio_rflx_i   (s2_dio_rflx),
        .dio_id_i     (s2_dio_id & PID_ANY | PID_ALL),  // (read only for a good pin)
        .dio_val_i    (s2_dio_val),
        .hold_o       (pkt_hold),
        .rep_req_o    (rep_req),
        .rep_n_o      (rep_n),
        .rep_data_o   (rep_data),
        .rep_tail_o   (rep_tail),
        .rep_done_i   (rep_done),
        .rep_new_o    (rep_new),
        .dio_new_o    (dio_rflx_new),
        .dio_id_o     (dio_rflx_id),
        .dio_val_o    (dio_rflx_val)
    );

    bsd_cfg_regs #(
        .NUM_PINS   (NUM_PINS),
        .FIXED_MASK (FIXED_MASK),
        .FIXED_CFG  (FIXED_CFG),
        .MEM_PINS   (MEM_FROM)
    ) u_cfg (
        .clk         (clk),
        .rst         (core_rst),
        .cfg_we_i    (cfg_we),
        .out_we_i    (out_we),
        .sel_i       (wr_pin_sel),
        .addr_i      (pkt_d1[5:0]),
        .rd_i        (pkt_valid),
        .cfg_wdata_i (cfg_wdata),
        .out_wdata_i (out_wdata),
        .cfg_o       (cfg),
        .out_o       (out_latch),
        .oe_o        (pin_oe),
        .watch_o     (pin_watch),
        .rd_cfg_o    (cfg_rd),
        .busy_o      (cfg_busy)
    );

    // --------------------------------------------------------- per-pin blocks
    // cfg is field-major: DIGCFG bit k of every pin is cfg[k*NUM_PINS +: NUM_PINS].
    wire [NUM_PINS-1:0] t_mode   = cfg[4*NUM_PINS +: NUM_PINS];
    wire [NUM_PINS-1:0] t_target = cfg[3*NUM_PINS +: NUM_PINS];

    assign pin_o = out_latch;

    bsd_trans_latch #(.WIDTH(NUM_PINS)) u_latch (
        .clk      (clk),
        .rst      (core_rst),
        .arm_i    (rearm | (FIXED_ENA & {NUM_PINS{init_arm}})),
        .watch_i  (pin_watch),
        .trg_i    (cfg[2*NUM_PINS +: NUM_PINS]),
        .sample_i (poll),
        .level_i  (level),
        .fire_o   (raw_trans)
    );

    // --------------------------------------------------------------- timers
    genvar p;
    wire [NT-1:0]       t_level, t_start, t_tmode, t_tstate, t_busy;
    wire [NT-1:0]       timer_run, timer_host_pend, timer_rflx_pend;
    wire [NT-1:0]       timer_expire;
    wire [NT-1:0]       ev_r, ev_f;
    wire                ev_any;
    wire [15:0]         t_count;
    wire                host_done, rflx_done;
    wire [5:0]          host_idx, rflx_idx;

    // Pin vectors to timer vectors and back (wiring only).
    generate
        if (TIMERS == 0) begin : g_no_timers
            assign t_level  = 1'b0;
            assign t_start  = 1'b0;
            assign t_tmode  = 1'b0;
            assign t_tstate = 1'b0;
            assign timer_busy = {NUM_PINS{1'b0}};
            wire unused_no_timers = ^{timer_start, t_mode, t_target, t_busy};
        end else begin : g_timers
            // A start takes its pin's TMODE and TSTATE on its clock: each pin's
            // flops, or with the memory the read of the packet's pin, which is on
            // every line (given as one bit: gathered bit by bit, a simulator built
            // the word on every clock).
            for (p = 0; p < NT; p = p + 1) begin : g_gather
                localparam integer PIN = pin_of_timer(p);
                assign t_level[p]  = level[PIN];
                assign t_start[p]  = timer_start[PIN];
                if (NUM_PINS < MEM_FROM) begin : g_mode
                    assign t_tmode[p]  = t_mode[PIN];
                    assign t_tstate[p] = t_target[PIN];
                end
            end
            if (NUM_PINS >= MEM_FROM) begin : g_cfg_mem
                assign t_tmode  = {NT{t_mode[0]}};
                assign t_tstate = {NT{t_target[0]}};
                // (every line is the same bit)
                wire unused_mode = ^{t_mode[NUM_PINS-1:1], t_target[NUM_PINS-1:1]};
            end
            for (p = 0; p < NUM_PINS; p = p + 1) begin : g_scatter
                if (TIMER_MASK[p]) begin : g_t
                    localparam integer T = count_below(p);
                    assign timer_busy[p] = t_busy[T];
                end else begin : g_n
                    assign timer_busy[p] = 1'b0;
                    // The executor never starts a timer on this pin, and TMODE
                    // and TSTATE are only stored here.
                    wire unused_pin = ^{timer_start[p], t_mode[p], t_target[p]};
                end
            end
        end
    endgenerate

    bsd_timer_bank #(.NUM_TIMERS(NT)) u_timers (
        .clk         (clk),
        .rst         (core_rst),
        .tick_i      (tick),
        .level_i     (t_level),
        .start_i     (t_start),
        .mode_i      (t_tmode),
        .target_i    (t_tstate),
        .host_i      (timer_host),
        .rflx_i      (timer_rflx),
        .expire_i    (timer_expire),
        .host_done_i (host_done),
        .host_idx_i  (host_idx),
        .rflx_done_i (rflx_done),
        .rflx_idx_i  (rflx_idx),
        .busy_o      (t_busy),
        .run_o       (timer_run),
        .run_host_o  (timer_host_pend),
        .run_rflx_o  (timer_rflx_pend),
        .ev_r_o      (ev_r),
        .ev_f_o      (ev_f),
        .ev_any_o    (ev_any),
        .t_o         (t_count)
    );

    bsd_timeout_wheel #(.NUM_TIMERS(NT)) u_wheel (
        .clk         (clk),
        .rst         (core_rst),
        .tick_i      (tick),
        .t_i         (t_count),
        .start_i     (t_start),
        .start_any_i (timer_go),
        .start_idx_i (timer_idx),
        .run_i       (timer_run),
        .expire_o    (timer_expire)
    );

    // ----------------------------------------------------------- heartbeat
    wire       hb_req, hb_done, hb_new;
    // Bits 7:1 are constant 0; bit 0 is bsd_heartbeat's down_q, whose toggles count there.
    /* verilator coverage_off */
    wire [7:0] hb_type;
    /* verilator coverage_on */

    bsd_heartbeat #(.HB_RATE(HB_RATE)) u_hb (
        .clk           (clk),
        .rst           (core_rst),
        .tick_i        (tick),
        .answer_i      (hb_answer),
        .answer_down_i (hb_answer_down),
        .req_o         (hb_req),
        .new_o         (hb_new),
        .type_o        (hb_type),
        .done_i        (hb_done),
        .link_up_o     (link_up)
    );

    // A heartbeat's event is the clock it falls due, like a timer's or a
    // reply's: registered here as theirs are in their blocks.
    reg hb_new_q;
    always @(posedge clk) begin
        hb_new_q <= hb_new;
        if (core_rst) hb_new_q <= 1'b0;
    end

    // ---------------------------------------------------------- event queue
    // At most two events per timer (reference, finish) wait before its result
    // is delivered, one reply and one heartbeat; DIG_IO RFLX values come one
    // per command (4 clocks at least, and none while a reply waits) and the
    // drain takes an item a clock: 2 NT + 8 entries never overflow
    // (docs/DESIGN.md). Both queues are sized by the timer count, so that a
    // few-timer build keeps short pointers (16 and 8 deep for GP 1.0, 256 and
    // 128 with 64 timers); a block RAM holds either. An entry without timer
    // events (a reply, a DIG_IO value, a heartbeat) skips the queue when
    // nothing waits in it and the drain is empty: 2 clocks less latency, and
    // the mux is only as wide as those fields.
    localparam integer EVQ_DEPTH  = 1 << $clog2(2 * NT + 8);
    localparam integer OUTQ_DEPTH = 1 << $clog2(NT + 4);
    wire          evq_ready, evq_valid, evq_empty, drain_free, drain_empty;
    wire [EW-1:0] evq_data;
    // (After a cmdRESET that turned the packet on offer into the power-up
    // message, the reply slot gives that message no event: bsd_pkt_tx's swap_o.)
    wire          ev_new   = ev_any || rep_new || dio_rflx_new || hb_new_q;
    wire [EW-1:0] ev_entry = {ev_any, ev_r, ev_f, rep_new, dio_rflx_new, hb_new_q, dio_rflx_id, dio_rflx_val,
                              t_count};
    // (drain_empty comes from flops: the drain's pick stays off the queue's
    // write enable; an entry that meets the drain's last item is queued.)
    wire          ev_skip  = evq_empty && drain_empty && !ev_any;

    bsd_fifo #(.WIDTH(EW), .DEPTH(EVQ_DEPTH), .SKID(0)) u_evq (
        .clk           (clk),
        .rst           (core_rst),
        .s_axis_tdata  (ev_entry),
        .s_axis_tvalid (ev_new && !ev_skip),
        .s_axis_tready (evq_ready),
        .m_axis_tdata  (evq_data),
        .m_axis_tvalid (evq_valid),
        .m_axis_tready (drain_free),
        .empty_o       (evq_empty)
    );

    wire        order_valid;
    wire [29:0] order_data;

    // A skipping entry has no timer event, and the drain reads T only for
    // timer events: T needs no mux, and r and f none either (the drain masks
    // them with ev_timers_i).
    // (the DIG_IO value's ID, bits 6:1 of the middle field, as constant as it is: one mask
    // over the whole word, which a simulator applies with two operations)
    // (The skipping entry's fields are named, not sliced from ev_entry: ev_entry then has a
    // single reader, the queue's write, and a simulator builds it only on a write's clock.)
    localparam [DW-1:0] EV_KEEP = {{(DW - 26){1'b1}}, 3'b111, PID_ANY, 1'b1, 16'hFFFF};
    localparam [DW-1:0] EV_SET  = {{(DW - 26){1'b0}}, 3'b000, PID_ALL, 1'b0, 16'h0000};
    wire [DW-1:0] ev_data = {evq_data[DW-1:26],
                             evq_valid ? evq_data[25:16] :
                                         {rep_new, dio_rflx_new, hb_new_q, dio_rflx_id, dio_rflx_val},
                             evq_data[15:0]} & EV_KEEP | EV_SET;

    bsd_drain #(
        .NUM_PINS      (NUM_PINS),
        .TIMER_MASK    (TIMER_MASK),
        .TIMER_ID_BASE (TIMER_ID_BASE),
        .NT            (NT),
        .DIO_ID_LO     (PIN_ID_BASE),
        .DIO_ID_HI     (PIN_ID_BASE + NUM_PINS - 1),
        .MEM_TIMERS    (MEM_FROM)
    ) u_drain (
        .clk           (clk),
        .rst           (core_rst),
        .ev_valid_i    (evq_valid || (ev_new && ev_skip)),
        .ev_data_i     (ev_data),
        .ev_timers_i   (evq_valid && evq_data[EW-1]),
        .ev_ready_o    (drain_free),
        .empty_o       (drain_empty),
        .run_host_i    (timer_host_pend),
        .run_rflx_i    (timer_rflx_pend),
        .start_i       (timer_go),
        .start_idx_i   (timer_idx),
        .start_host_i  (timer_host),
        .start_rflx_i  (timer_rflx),
        .hold_o        (drain_hold),
        .order_valid_o (order_valid),
        .order_data_o  (order_data),
        .rflx_done_o   (rflx_done),
        .rflx_idx_o    (rflx_idx),
        .rflx_valid_o  (rflx_valid),
        .rflx_id_o     (rflx_id),
        .rflx_data_o   (rflx_data)
    );

    // -------------------------------------------------------------- output
    // One item per packet that can wait: a timer's result each, the reply,
    // the heartbeat: NT + 2 at most (OUTQ_DEPTH is NT + 4 or more). An item
    // skips the queue when nothing waits in it and the transmitter is idle.
    wire        outq_ready, outq_valid, outq_empty, tx_free, tx_take, tx_idle;
    wire [29:0] outq_data;
    // (tx_idle comes from flops, like drain_empty above.)
    wire        out_skip = outq_empty && tx_idle;

    bsd_fifo #(.WIDTH(30), .DEPTH(OUTQ_DEPTH), .SKID(0)) u_outq (
        .clk           (clk),
        .rst           (core_rst),
        .s_axis_tdata  (order_data),
        .s_axis_tvalid (order_valid && !out_skip),
        .s_axis_tready (outq_ready),
        .m_axis_tdata  (outq_data),
        .m_axis_tvalid (outq_valid),
        .m_axis_tready (tx_free),
        .empty_o       (outq_empty)
    );

    bsd_pkt_tx #(.MODULE_ADDR(MODULE_ADDR)) u_tx (
        .clk           (clk),
        .rst           (rst),
        .flush_i       (soft_rst_q),
        .swap_o        (tx_swap),
        .item_valid_i  (outq_valid || (order_valid && out_skip)),
        // (the timer's number and device ID as constant as they are)
        .item_data_i   ((outq_valid ? outq_data : order_data) & {2'b11, TIDX_MASK, TID_ANY, 16'hFFFF} |
                        {8'd0, TID_ALL, 16'd0}),
        .item_ready_o  (tx_take),
        .free_o        (tx_free),
        .idle_o        (tx_idle),
        .rep_n_i       (rep_n),
        .rep_data_i    (rep_data),
        .rep_tail_i    (rep_tail),
        .hb_type_i     (hb_type),
        .timer_done_o  (host_done),
        .timer_idx_o   (host_idx),
        .reply_done_o  (rep_done),
        .hb_done_o     (hb_done),
        .m_axis_tdata  (m_axis_tdata),
        .m_axis_tvalid (m_axis_tvalid),
        .m_axis_tready (m_axis_tready),
        .m_axis_tlast  (m_axis_tlast)
    );

    // The queues never fill (sized above), and the heartbeat's request is
    // followed through its item.
    // The executor takes d0 decoded (pkt_cmd), not the byte.
    wire unused_top = ^{evq_ready, outq_ready, tx_take, hb_req, rep_req, pkt_d0};

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block
    // The sizing argument above, checked in every simulation: no entry or item is refused.
    // (nested, the rare condition first, so that a simulator tests one bit a clock)
    // A check that fires only on a design error: no run reaches its branches, so they
    // are no coverage points.
    /* verilator coverage_off */
    always @(posedge clk) begin
        if (!evq_ready) begin
            if (!rst && ev_new && !ev_skip)
                $fatal(1, "brainstem_dio: the event queue is full (an entry would be lost)");
        end
        if (!outq_ready) begin
            if (!rst && order_valid && !out_skip)
                $fatal(1, "brainstem_dio: the output queue is full (a packet would be lost)");
        end
    end
    /* verilator coverage_on */
`endif
`endif
endmodule
`default_nettype wire
