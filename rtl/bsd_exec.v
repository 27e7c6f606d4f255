// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Executes one packet from the parser in two clocks. The first looks up the
// addressed pin's state (an AND-OR over the pins with the pin's one-hot,
// which the parser registers with d1, so that no decoder of d1 is in series
// with the lookups and the strobes' clears),
// decides the state changes (configuration and output writes, re-arms, timer
// starts, the heartbeat answer) into registers, so that those strobes leave
// this module straight from flops, and decides the reply as far as the
// packet alone tells, with the contract's precedence (cmdInvalid,
// cmdTooShort, the command's own error, then the action and cmdTooLong). The
// second drives the strobes and completes the reply with what the pin's
// IODIR and its timer's start decide (and a DIG_CFG read's other DIGCFG
// bits, looked up there), and whether a DIG_IO read sends its value on
// RFLX. Packets come at least three clocks apart, so the stages never
// overlap. cmdDEBUG's echo takes d3..d7, and the strobes' pin (pin_sel_o)
// d1's one-hot, straight from the parser's registers in stage 2: the parser
// writes none of the packet's data bytes before the clock after stage 2,
// when the reply slot has taken them (a slot past the packet's N may take
// the next byte, but such a packet never reads it). The decision goes to
// bsd_reply_slot, which holds the waiting reply and the waiting DIG_IO RFLX
// value and tells the parser when to hold.
module bsd_exec #(
    parameter integer        NUM_PINS    = 5,
    parameter [NUM_PINS-1:0] TIMER_MASK  = 5'b11110,
    parameter [NUM_PINS-1:0] FIXED_MASK  = 0,
    parameter integer        PIN_ID_BASE = 5,
    // 1: bsd_cfg_regs keeps DIGCFG bits 4:1 in its memory (from its MEM_PINS
    // pins on), and a DIG_CFG read takes them from cfg_rd_i.
    parameter [0:0]          CFG_MEM     = 1'b0
) (
    input  wire                  clk,
    input  wire                  rst,
    // packet from bsd_parser
    input  wire                  pkt_valid_i,
    input  wire [1:0]            pkt_kind_i,
    input  wire [3:0]            pkt_n_i,
    input  wire [7:0]            pkt_cmd_i,     // d0 decoded (bsd_parser's pkt_cmd_o)
    input  wire [7:0]            pkt_d1_i,
    /* verilator lint_off UNUSEDSIGNAL */  // (with CFG_MEM, d1_sel below)
    input  wire [NUM_PINS-1:0]   pkt_sel_i,     // d1's bits 5:0 one-hot (bsd_parser's pkt_sel_o)
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [7:0]            pkt_d2_i,
    input  wire [39:0]           pkt_tail_i,    // d3..d7 (cmdDEBUG)
    // pin state
    // (with CFG_MEM, only IODIR, bits 0 of each pin, is read: cfg_rd_i has the rest)
    /* verilator lint_off UNUSEDSIGNAL */
    input  wire [5*NUM_PINS-1:0] cfg_i,
    // with CFG_MEM: d1's pin's DIGCFG bits 4:1, from the clock after the packet's
    // (bsd_cfg_regs's memory read on that clock); unused without it
    input  wire [3:0]            cfg_rd_i,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [NUM_PINS-1:0]   level_i,
    input  wire [NUM_PINS-1:0]   timer_busy_i,
    // configuration register file
    output wire                  cfg_we_o,
    output wire                  out_we_o,
    output wire [NUM_PINS-1:0]   pin_sel_o,     // the pin both writes address, one-hot or zero
                                                // (d1's pin, one-hot; read only with the write strobes)
    output wire [4:0]            cfg_wdata_o,
    output wire                  out_wdata_o,
    output wire [NUM_PINS-1:0]   rearm_o,
    // timers: start one, with the DEVCODE's delivery bits
    output wire [NUM_PINS-1:0]   timer_start_o,
    output wire                  timer_go_o,    // a timer starts (timer_start_o is not zero)
    output wire [5:0]            timer_idx_o,   // and its number (timers counted in pin order)
    output wire                  timer_host_o,
    output wire                  timer_rflx_o,
    // heartbeat answer from the host
    output wire                  hb_answer_o,       // the host answered a heartbeat: type 2 (UP) or 3 (DOWN)
    output wire                  hb_answer_down_o,  // it answered a DOWN one
    // cmdRESET: the core returns to its power-up state (a one-clock strobe in stage 2)
    output wire                  soft_reset_o,
    // stage 2's packet and decision, for bsd_reply_slot
    output wire                  s2_valid_o,    // a packet is in stage 2
    output wire                  reply_o,       // it has a reply: A, reply_n_o, reply_data_o[31:24] ...
    output wire [3:0]            reply_n_o,
    output wire [31:0]           reply_data_o,
    output wire [31:0]           reply_tail_o,  // d4..d7 of a cmdDEBUG echo (stale otherwise)
    output wire                  dio_rflx_o,    // it is a DIG_IO read that sends its value on RFLX
    output wire [5:0]            dio_id_o,      // the DIG_IO pin's device ID
    output wire                  dio_val_o      // and its level
);
    `include "bsd_protocol.vh"

    localparam integer IODIR = 0;  // DIGCFG bit: 1 = input
    localparam [7:0] NUM_PINS_W = NUM_PINS[7:0];

    // x < K for a constant K, as gates: synthesis folds the constant into a
    // few LUTs where a comparator would take a carry chain.
    function below(input [7:0] x, input [7:0] k);
        integer j;
        reg     eq;
        begin
            below = 1'b0;
            eq    = 1'b1;
            for (j = 7; j >= 0; j = j - 1) begin
                below = below | (eq & k[j] & ~x[j]);
                eq    = eq & (x[j] == k[j]);
            end
        end
    endfunction
    localparam [5:0] PIN_ID_W   = PIN_ID_BASE[5:0];

    // The timer number of each pin (the timers on the pins below it), as a
    // table indexed by the packet's pin: the timer blocks take a start as its
    // number as well, so no one-hot-to-number encoder is built. Only a timer
    // pin's entry is ever used; the others (pins without a timer, and beyond
    // NUM_PINS) continue the count as if the pins above the last were timer
    // pins and a pin without one took the number below it, which keeps the
    // table a plain subtraction of the pin (all-timer builds: the pin itself),
    // cut to the bits a timer number has.
    // Only localparam initializers call them: they run while elaborating, never in simulation.
    /* verilator coverage_off */
    function integer timer_bits(input integer unused);
        integer q, t;
        begin
            t = 0;
            for (q = 0; q < NUM_PINS; q = q + 1)
                if (TIMER_MASK[q]) t = t + 1;
            timer_bits = 0;
            while ((1 << timer_bits) < t) timer_bits = timer_bits + 1;
        end
    endfunction
    function [64*6-1:0] timer_table(input integer unused);
        integer   q;
        reg [5:0] num, mask;
        reg [63:0] tm;
        begin
            tm = 64'd0;
            // bit by bit: a part select would overrun tm on a NUM_PINS > 64
            // build, which must reach the top's range check (Icarus aborts)
            for (q = 0; q < NUM_PINS && q < 64; q = q + 1) tm[q] = TIMER_MASK[q];
            mask = 6'd0;
            for (q = 0; q < timer_bits(0); q = q + 1) mask = {mask[4:0], 1'b1};
            num = 6'h3F;  // the pin before pin 0
            for (q = 0; q < 64; q = q + 1) begin
                if (q >= NUM_PINS || tm[q]) num = num + 6'd1;
                timer_table[6*q +: 6] = num & mask;
            end
        end
    endfunction
    /* verilator coverage_on */
    localparam [64*6-1:0] TIMER_NUM = timer_table(0);
    // Up to 8 timers, each start strobe's data is an AND of its own (the pin's
    // line, an input, not busy, a PTIME_RD of N >= 2), so that the lookups end
    // at the strobes' D inputs: the shared clear below (starts()) was the
    // iCEBreaker top's critical path, a reset input behind four LUT levels.
    // With CFG_MEM too: the one-hot is decoded from d1 there, so each bit's
    // AND folds into its own decode LUT, and the shared clear (d1's decode,
    // the lookups, 64 reset inputs) was uart64t's critical path, 33 ns (37
    // logic cells more). More timers otherwise keep the shared clear: no gate
    // a timer.
    localparam [0:0] FEW_TIMERS = timer_bits(0) <= 3;
    localparam [0:0] START_AND  = FEW_TIMERS || CFG_MEM;

    // ------------------------------ stage 1: pin lookup and decisions

    // Stage 1 decides everything about a packet at once, as one vector (the
    // flops it loads are listed below, in its order). It is a function,
    // called only in the branch of a packet's clock (and of reset): a
    // simulator decodes a packet on its clock only, where wires would be
    // worked out every clock; synthesis gives the same gates either way.
    localparam integer DW = 33 + 2 * NUM_PINS + 17;
    function [DW-1:0] stage1(input [1:0] kind, input [3:0] n, input [7:0] cmd, input [7:0] d1,
                             input [NUM_PINS-1:0] sel, input [NUM_PINS-1:0] in,
                             input [NUM_PINS-1:0] level,
                             input [NUM_PINS-1:0] busy);
        reg [5:0]          dev_pin;
        reg                is_cmd, d0_cfg, d0_io, d0_rst, d0_time, d0_dbg, d0_hb, d0_rset, d0_dig;
        reg                n_ge2, n_ge3, n1, n2, pin_ok, dev_ok, c_cfg, c_cfg_rd, c_out, c_rst, c_time;
        reg                look_level, look_in, sel_fixed, sel_timer;
        reg                cfg_w, rst_w, out_w, start, idx_err, m_inv, m_short, cfgerr, cfg_rd, dbg;
        reg                serial, probe, long;
        reg [7:0]          b0, b1;
        reg [3:0]          rn;
        begin
            // A `pin` byte is the whole byte; a DEVCODE's pin is bits 5:0.
            dev_pin = d1[5:0];

            // The packet's kind, command and length as single flags.
            is_cmd  = kind == KIND_CMD;
            // (d0 comes decoded, from flops: bsd_parser's pkt_cmd_o)
            d0_cfg  = cmd[CMDF_DIG_CFG];
            d0_io   = cmd[CMDF_DIG_IO];
            d0_rst  = cmd[CMDF_DIG_RST];
            d0_time = cmd[CMDF_PTIME_RD];
            d0_dbg  = cmd[CMDF_DEBUG];
            d0_hb   = cmd[CMDF_HB];
            d0_rset = cmd[CMDF_RESET];
            d0_dig  = d0_cfg || d0_io || d0_rst || d0_time;
            n_ge2   = |n[3:1];
            n_ge3   = |n[3:2] || &n[1:0];
            n1      = n == 4'd1;
            n2      = n == 4'd2;
            pin_ok  = below(d1, NUM_PINS_W);
            dev_ok  = below({2'b00, dev_pin}, NUM_PINS_W);
            c_cfg   = is_cmd && d0_cfg && n_ge3;    // a DIG_CFG write
            c_cfg_rd = is_cmd && d0_cfg && n2;      // a DIG_CFG read
            c_out   = is_cmd && d0_io && n_ge3;     // a DIG_IO write
            c_rst   = is_cmd && d0_rst && n_ge2;
            c_time  = is_cmd && d0_time && n_ge2;

            // The addressed pin as a one-hot (sel, from the parser's flops);
            // no line is set for a pin beyond NUM_PINS - 1. A `pin` byte must
            // match whole (bits 7:6 zero); a DEVCODE's pin is its bits 5:0.
            // The pin's IODIR, level and busy bit are picked with the one-hot
            // by an AND-OR (the DIG_CFG read's other bits in stage 2).

            // The addressed pin's state; zero for a pin beyond the last.
            look_level = |(level & sel);
            look_in    = |(in & sel);
            sel_fixed  = |(sel & FIXED_MASK);
            // (with a timer on every pin, that is "a pin at all": dev_ok, which is
            // cheap, where the OR over sel is not, synthesis not knowing sel
            // is zero exactly for a pin beyond the last)
            sel_timer  = &TIMER_MASK ? dev_ok : |(sel & TIMER_MASK);

            // The state changes are decided once, from the lookup, not per
            // pin: the pins see them as the registered one-hot and a strobe
            // each (a gate a pin for all of them, rather than a decision a pin
            // for each).

            // The reply, decided as far as the packet alone tells; stage 2 adds
            // what the pin's IODIR and its timer's start decide, and the
            // outcomes of d1's pin checks (flags, below), in a gate or two
            // between flops and the reply slot. A reply's bytes past its N are
            // never sent, so they are left as they fall.
            cfg_w   = c_cfg && pin_ok && !sel_fixed;   // a DIG_CFG write that writes
            rst_w   = c_rst && pin_ok;                 // a DIG_RST that re-arms
            out_w   = c_out && pin_ok && !look_in;     // a DIG_IO write that writes
            start   = starts(kind, n[3:1], cmd, sel, in, busy);
            idx_err = ((c_cfg || c_rst || c_out) && !pin_ok) || (c_cfg_rd && !pin_ok) ||
                      (is_cmd && d0_io && n2 && !dev_ok) ||
                      (c_time && !sel_timer);  // (no line of sel is set for a bad DEVCODE pin)
            m_inv   = is_cmd && !cmd[CMDF_ANY];
            m_short = is_cmd && d0_dig && n1;
            cfgerr  = c_cfg && pin_ok && sel_fixed;
            cfg_rd  = c_cfg_rd && pin_ok;
            dbg     = is_cmd && d0_dbg;
            serial  = kind == KIND_SERIAL;
            probe   = kind == KIND_PROBE;
            // Longest forms: DIG_CFG and DIG_IO take 3 bytes, DIG_RST and PTIME_RD 2.
            long    = (d0_cfg || d0_io) ? |n[3:2] : n_ge3;

            // b0, b1 and rn take only what the kind, command and N tell (a
            // DIG_CFG read's form counted as a read here): the outcomes that
            // need d1's pin (cfg_rd, idx_err, cfgerr, cfg_w || rst_w) go to
            // stage 2 as flags of their own, which override these bytes
            // there, so that the pin's checks are not in series with the
            // bytes' muxes on stage 1's clock. They are exclusive (d0 is
            // one-hot), and whenever one is set the bytes' other terms are
            // zero or overridden.
            b0 = probe ? 8'd0 : dbg ? CMD_DEBUG : CMD_MSG;
            b1 = (c_cfg_rd || dbg) ? d1 :
                 ({8{serial}}  & MSG_SERIAL_ERROR)  | ({8{m_inv}}   & MSG_CMD_INVALID) |
                 ({8{m_short}} & MSG_CMD_TOO_SHORT);
            rn = probe ? 4'd0 : dbg ? n : MSG_N[3:0];

            stage1 = {b0, b1, rn, idx_err, cfgerr, cfg_w || rst_w,
                      long, PIN_ID_W + dev_pin, look_in, look_level, sel_fixed,
                      TIMER_NUM[6*dev_pin +: 6],
                      // the flags, cleared on a clock without a packet
                      probe || serial || m_inv || m_short || cfgerr || idx_err || cfg_rd || dbg ||
                          (long && (cfg_w || rst_w)),       // known
                      c_out && pin_ok,                      // io_w
                      is_cmd && d0_io && n2 && dev_ok,      // io_r
                      c_time && sel_timer,                  // pt
                      start,                                // started
                      cfg_rd, dbg,
                      is_cmd && d0_rset,                    // reset
                      cfg_w, out_w,                         // cfg_we, out_we
                      is_cmd && d0_hb && n_ge2 &&           // hb_answer
                          (d1 == HB_UP + HB_ANSWER_OFFSET || d1 == HB_DOWN + HB_ANSWER_OFFSET),
                      sel,                                  // rearm (cleared below unless rearms())
                      START_AND ? sel & TIMER_MASK & in & ~busy & {NUM_PINS{c_time}} :  // start (with many
                                   sel & TIMER_MASK};       // timers cleared below unless starts())
        end
    endfunction

    // Whether the packet re-arms its pin (cfg_w || rst_w above), for the
    // re-arm strobes' clear: an if, not an AND per pin, so that synthesis
    // gives the condition all pins share to the flops' synchronous reset.
    function rearms(input [1:0] kind, input [3:0] n, input [7:0] cmd, input [7:0] d1,
                    input [NUM_PINS-1:0] sel);
        begin
            rearms = kind == KIND_CMD && below(d1, NUM_PINS_W) &&
                     ((cmd[CMDF_DIG_CFG] && (|n[3:2] || &n[1:0]) && !(|(sel & FIXED_MASK))) ||
                      (cmd[CMDF_DIG_RST] && |n[3:1]));
        end
    endfunction

    // Whether the packet starts its pin's timer: stage 1's `start`, and with
    // more than 8 timers (without CFG_MEM) the start strobes' clear, as rearms() is the re-arm
    // strobes': the strobes then load the pin's one-hot line, and the start
    // is their shared synchronous clear, not an AND a timer.
    function starts(input [1:0] kind, input [3:1] n, input [7:0] cmd, input [NUM_PINS-1:0] sel,
                    input [NUM_PINS-1:0] in, input [NUM_PINS-1:0] busy);
        begin
            starts = kind == KIND_CMD && cmd[CMDF_PTIME_RD] && |n[3:1] &&
                     |(in & sel & TIMER_MASK) && !(|(busy & sel & TIMER_MASK));
        end
    endfunction

    reg                s2_valid_q;
    reg                known_q;       // a reply the packet alone decides
    reg [7:0]          b0_q, b1_q;    // its first two bytes
    reg [3:0]          rn_q;          // and its N
    reg                idx_err_q, cfgerr_q, tl_q;  // cmdIndexErr, configErr, cmdTooLong by d1's pin
    reg                io_w_q;        // a DIG_IO write to a good pin: cmdIndexErr if an input
    reg                io_r_q;        // a DIG_IO read of a good pin: cmdIndexErr unless an input
    reg                pt_q;          // a PTIME_RD of a timer pin: cmdIndexErr unless an input,
                                      // tmrConflict unless started
    reg                started_q;     // a timer started
    reg                long_q;        // longer than the command's longest form
    reg                cfg_rd_q, dbg_q;
    reg                reset_q;       // cmdRESET
    reg [2:0]          s2_d1_q;       // d1's bits 7 (HOST), 6 (RFLX) and 0
    reg [7:0]          s2_d2_q;
    reg [5:0]          dev_id_q;      // the DIG_IO pin's device ID
    reg                pin_in_q;      // the pin's IODIR
    reg                pin_level_q, pin_fixed_q;
    reg                cfg_we_q, out_we_q, hb_answer_q;
    reg [NUM_PINS-1:0] rearm_q;

    // The packet's pin as a one-hot: the parser's flops (pkt_sel_i), or with
    // CFG_MEM decoded here from d1 (which the parser holds on the clock after
    // the packet's as well, for pin_sel_o). With the memory no lookup of
    // stage 2 reads the one-hot, and the decode folds into its readers' LUTs
    // (the strobes' flops, bsd_cfg_regs's write AND-ORs), so the parser's
    // flop a pin, each an iCE40 logic cell alone, goes (uart64t: 35 cells
    // fewer); without it, stage 2's DIG_CFG read looks up four fields with it,
    // cheaper from flops (below).
    localparam [NUM_PINS-1:0] SEL_ONE = 1;
    wire [NUM_PINS-1:0] d1_sel;
    generate
        if (CFG_MEM) begin : g_d1_sel
            assign d1_sel = SEL_ONE << pkt_d1_i[5:0];
        end else begin : g_pkt_sel
            assign d1_sel = pkt_sel_i;
        end
    endgenerate
    reg [NUM_PINS-1:0] start_q;
    reg [5:0]          tidx_q;        // the packet pin's timer number

    // Stage 1's decision is loaded only on a packet's clock: the data flops
    // (reply bytes, d1/d2, the lookup) hold between packets (enabled flops,
    // SB_DFFE; they load in reset too, so no flop is left unknown); the flags
    // and strobes are cleared on a clock without a packet and in reset (one
    // synchronous clear that every flag shares).
    always @(posedge clk) begin
        s2_valid_q <= pkt_valid_i;
        if (pkt_valid_i || rst) begin
            {b0_q, b1_q, rn_q, idx_err_q, cfgerr_q, tl_q, long_q, dev_id_q, pin_in_q, pin_level_q, pin_fixed_q, tidx_q,
             known_q, io_w_q, io_r_q, pt_q, started_q, cfg_rd_q, dbg_q, reset_q, cfg_we_q, out_we_q,
             hb_answer_q, rearm_q, start_q} <= stage1(pkt_kind_i, pkt_n_i, pkt_cmd_i, pkt_d1_i, d1_sel,
                                                      cfg_i[IODIR*NUM_PINS +: NUM_PINS], level_i,
                                                      timer_busy_i);
            s2_d1_q     <= {pkt_d1_i[7:6], pkt_d1_i[0]};
            s2_d2_q     <= pkt_d2_i;
        end
        if (rst || !pkt_valid_i) begin
            s2_valid_q  <= 1'b0;
            known_q     <= 1'b0;
            io_w_q      <= 1'b0;
            io_r_q      <= 1'b0;
            pt_q        <= 1'b0;
            started_q   <= 1'b0;
            cfg_rd_q    <= 1'b0;
            dbg_q       <= 1'b0;
            reset_q     <= 1'b0;
            cfg_we_q    <= 1'b0;
            out_we_q    <= 1'b0;
            hb_answer_q <= 1'b0;
            rearm_q     <= {NUM_PINS{1'b0}};
            start_q     <= {NUM_PINS{1'b0}};
        end else begin
            if (!rearms(pkt_kind_i, pkt_n_i, pkt_cmd_i, pkt_d1_i, d1_sel))
                rearm_q <= {NUM_PINS{1'b0}};
            if (!START_AND && !starts(pkt_kind_i, pkt_n_i[3:1], pkt_cmd_i, d1_sel,
                                       cfg_i[IODIR*NUM_PINS +: NUM_PINS], timer_busy_i))
                start_q <= {NUM_PINS{1'b0}};
        end
    end

    // ---------------------------------------------------- stage 2: execute
    wire       dev_host = s2_d1_q[2];
    wire       dev_rflx = s2_d1_q[1];
    wire       in       = pin_in_q;

    assign cfg_we_o      = cfg_we_q;
    assign out_we_o      = out_we_q;
    assign rearm_o       = rearm_q;
    assign timer_start_o = start_q;
    assign timer_go_o    = started_q;
    assign timer_idx_o   = tidx_q;
    assign hb_answer_o   = hb_answer_q;
    assign pin_sel_o     = d1_sel;
    assign cfg_wdata_o   = s2_d2_q[4:0];
    assign out_wdata_o   = s2_d2_q != 8'd0;
    assign timer_host_o  = dev_host;
    assign timer_rflx_o  = dev_rflx;
    assign hb_answer_down_o = s2_d1_q[0];  // type 3, as hb_answer_o comes only for 2 and 3
    // Any N: the power-up message that follows is the answer, so it is never cmdTooLong.
    assign soft_reset_o  = reset_q;

    // The three commands whose outcome needs the pin's IODIR (and the start):
    //   DIG_IO write    input: cmdIndexErr; output: written (cmdTooLong if long)
    //   DIG_IO read     input: the value (a reply only for the host bit); output: cmdIndexErr
    //   PTIME_RD        input and started: (cmdTooLong if long); input, busy: tmrConflict;
    //                   output: cmdIndexErr
    assign s2_valid_o   = s2_valid_q;
    assign reply_o      = known_q || (io_w_q && (in || long_q)) || (io_r_q && (!in || dev_host)) ||
                          (pt_q && (!in || !started_q || long_q));
    assign reply_n_o    = io_r_q ? (in ? 4'd3 : MSG_N[3:0]) : cfg_rd_q ? 4'd3 : rn_q;
    assign reply_data_o[31:24] = io_r_q ? (in ? CMD_DEV_VAL : CMD_MSG) : cfg_rd_q ? CMD_DIG_CFG : b0_q;
    assign reply_data_o[23:16] = io_w_q ? (in ? MSG_CMD_INDEX_ERR : MSG_CMD_TOO_LONG) :
                                 io_r_q ? (in ? {2'b00, dev_id_q} : MSG_CMD_INDEX_ERR) :
                                 pt_q   ? (!in ? MSG_CMD_INDEX_ERR :
                                           started_q ? MSG_CMD_TOO_LONG : MSG_TMR_CONFLICT) :
                                 // (configErr and cmdTooLong come only with b1_q zero, so they
                                 // are ORed in; cmdIndexErr can come with b1_q = d1, a DIG_CFG
                                 // read of a pin beyond the last)
                                 (idx_err_q ? MSG_CMD_INDEX_ERR : b1_q) |
                                     ({8{cfgerr_q}} & MSG_CONFIG_ERR) | ({8{tl_q}} & MSG_CMD_TOO_LONG);
    // The DIG_CFG read's DIGCFG bits 4:1 of the pin (pkt_sel_i) are looked
    // up here, not in stage 1 (only the reply needs them): an AND-OR over the
    // pins with a select that comes from flops takes about half the LUTs of
    // one with the select decoded in the same clock, whose decoder synthesis
    // merges into each field's mux (64 pins: ~40 LUT4 a field, not ~90).
    // cfg_i's bits 4:1 of the pin are as on stage 1's clock (only this
    // packet's stage 2 writes them, from the clock after). With CFG_MEM they
    // are bsd_cfg_regs's read of d1's pin on stage 1's clock, cfg_rd_i from
    // this clock on, and there is no lookup (uart64t: 64 logic cells
    // fewer; the memory shows bits 4, 3 and 1 on every line of cfg_i too, but
    // synthesis does not see that an AND-OR of one bit is that bit). (A ?:
    // with the AND-ORs written out, not an AND or a function, so that a
    // simulator works them out only for a read.)
    assign reply_data_o[15:8]  = (cfg_rd_q ? {pin_fixed_q, 2'b00,
                                              CFG_MEM ? cfg_rd_i : {|(cfg_i[4*NUM_PINS +: NUM_PINS] & pkt_sel_i),
                                                                    |(cfg_i[3*NUM_PINS +: NUM_PINS] & pkt_sel_i),
                                                                    |(cfg_i[2*NUM_PINS +: NUM_PINS] & pkt_sel_i),
                                                                    |(cfg_i[1*NUM_PINS +: NUM_PINS] & pkt_sel_i)},
                                              pin_in_q} : 8'd0) |
                                 ({8{dbg_q}} & s2_d2_q) | {7'd0, io_r_q && pin_level_q};
    assign reply_data_o[7:0]   = pkt_tail_i[39:32];   // only cmdDEBUG's echo sends it
    // A DIG_IO read of an input pin with the RFLX bit (bsd_reply_slot).
    assign dio_rflx_o   = io_r_q && in && dev_rflx;
    assign reply_tail_o = pkt_tail_i[31:0];
    assign dio_id_o     = dev_id_q;
    assign dio_val_o    = pin_level_q;

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the formal props assert it
    // Packets come at least three clocks apart (the two stages never overlap).
    reg chk_pkt1_q, chk_pkt2_q;
    always @(posedge clk) begin
        if (pkt_valid_i) begin  // (nested: a simulator tests one bit on a clock without a packet)
            if (!rst && (chk_pkt1_q || chk_pkt2_q))
                $fatal(1, "bsd_exec: a packet %0d clock(s) after the previous one (at least 3 apart)",
                       chk_pkt1_q ? 1 : 2);
        end
        chk_pkt1_q <= pkt_valid_i && !rst;
        chk_pkt2_q <= chk_pkt1_q && !rst;
    end
`endif
`endif

`ifdef FORMAL
`include "bsd_exec_props.vh"
`endif
endmodule
`default_nettype wire
