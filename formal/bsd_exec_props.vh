// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_exec (included at the end of the module under `ifdef FORMAL).
// Assumed, as bsd_parser hands packets over: reset on the first clock; packets at least three
// clocks apart (the header's comment-only invariant; in simulation the block checks it);
// kind CMD, PROBE or SERIAL; a command's N 1..8, a probe's 0; pkt_cmd_i the flags of a free
// d0 byte (f_pkt_d0), as bsd_parser decodes it, and pkt_sel_i d1's pin one-hot on every clock
// (its props prove both); the packet's own data bytes (d1 for N >= 2, d3..d(N-1) of
// pkt_tail_i) unchanged on the clock after pkt_valid_i, as the parser's props prove (a slot past
// N may take the next byte there, so stage 2 must not need it).
// cfg_i, level_i and timer_busy_i are free; they count as they are on pkt_valid_i's clock,
// but for a DIG_CFG read's bits 4:1, which stage 2 looks up in cfg_i as it is then, or with
// CFG_MEM takes from cfg_rd_i (free too: bsd_cfg_regs's read of the pin on stage 1's clock).
// cfg_i is field-major (bsd_cfg_regs): DIGCFG bit k of pin p is cfg_i[k*NUM_PINS + p].
// Asserted against a reference decoder written from PROTOCOL.md §2/§3 (precedence
// cmdInvalid, cmdTooShort, the command's own error, then the action and cmdTooLong): the
// clock after each packet (s2_valid_o, exactly then, never two clocks in a row) the
// state-change strobes (cfg_we_o, out_we_o, rearm_o, timer_start_o, hb_answer_o) are the
// reference's, with their pin (pin_sel_o, one-hot), data and delivery bits (and the timer's
// number, timer_idx_o, with timer_go_o set exactly with a start); the reply (reply_o, N, the bytes up to
// N, the echo's tail) and dio_rflx_o (with the pin's device ID and level) are the
// reference's; on every other clock no strobe, no reply, no RFLX value: one decision per
// packet, each strobe one clock long. pin_sel_o, rearm_o and timer_start_o are one-hot or zero.
    reg                  f_past_valid = 1'b0;
    (* anyseq *) wire [7:0] f_pkt_d0;   // the packet's d0, which pkt_cmd_i decodes
    wire [6:0]           f_cmdf = {f_pkt_d0 == CMD_PTIME_RD, f_pkt_d0 == CMD_DIG_RST, f_pkt_d0 == CMD_DIG_IO,
                                   f_pkt_d0 == CMD_DIG_CFG, f_pkt_d0 == CMD_RESET, f_pkt_d0 == CMD_DEBUG,
                                   f_pkt_d0 == CMD_HB};
    reg                  f_s2, f_s2_q, f_p2;
    reg [1:0]            f_kind;
    reg [3:0]            f_n;
    reg [7:0]            f_d0, f_d1, f_d2;
    reg [39:0]           f_tail;
    reg [5*NUM_PINS-1:0] f_cfg;
    reg [NUM_PINS-1:0]   f_level, f_busy;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_s2   <= pkt_valid_i && !rst;
        f_s2_q <= f_s2;
        f_p2   <= f_s2;   // a packet two clocks ago
        if (pkt_valid_i) begin
            f_kind  <= pkt_kind_i;
            f_n     <= pkt_n_i;
            f_d0    <= f_pkt_d0;
            f_d1    <= pkt_d1_i;
            f_d2    <= pkt_d2_i;
            f_tail  <= pkt_tail_i;
            f_cfg   <= cfg_i;
            f_level <= level_i;
            f_busy  <= timer_busy_i;
        end
        if (rst) begin
            f_s2   <= 1'b0;
            f_s2_q <= 1'b0;
            f_p2   <= 1'b0;
        end
    end

    // The reference decision for the packet captured (meaningful with f_s2).
    wire [5:0] f_dp     = f_d1[5:0];             // a DEVCODE's pin
    // The DEVCODE pin's timer number: the timers on the pins below it.
    reg [6:0] f_tnum;
    integer   f_t;
    always @(*) begin
        f_tnum = 7'd0;
        for (f_t = 0; f_t < NUM_PINS; f_t = f_t + 1)
            if (TIMER_MASK[f_t] && f_t < f_dp) f_tnum = f_tnum + 7'd1;
    end

    wire       f_cmd    = f_kind == KIND_CMD;
    wire       f_pin_ok = f_d1 < NUM_PINS;       // a whole `pin` byte
    wire       f_dev_ok = f_dp < NUM_PINS;
    wire       f_is_in  = f_pin_ok && f_cfg[f_d1[5:0]];     // the pin byte's pin is an input
    wire       f_dev_in = f_dev_ok && f_cfg[f_dp];          // the DEVCODE's pin is an input
    // The pin byte's pin's DIGCFG bits 4:0 (meaningful with f_pin_ok).
    // (bits 4:1 as cfg_i, or with CFG_MEM cfg_rd_i, has them on stage 2's clock, IODIR as on
    // stage 1's: see the header)
    wire [4:0] f_pin_cfg = {CFG_MEM ? cfg_rd_i :
                                      {cfg_i[4*NUM_PINS + f_d1[5:0]], cfg_i[3*NUM_PINS + f_d1[5:0]],
                                       cfg_i[2*NUM_PINS + f_d1[5:0]], cfg_i[NUM_PINS + f_d1[5:0]]},
                            f_cfg[f_d1[5:0]]};
    wire       f_valid_code = f_d0 == CMD_HB || f_d0 == CMD_DIG_CFG || f_d0 == CMD_DIG_IO ||
                              f_d0 == CMD_DIG_RST || f_d0 == CMD_PTIME_RD || f_d0 == CMD_DEBUG ||
                              f_d0 == CMD_RESET;
    wire       f_reset  = f_cmd && f_d0 == CMD_RESET;
    wire       f_w_cfg  = f_cmd && f_d0 == CMD_DIG_CFG && f_n >= 3 && f_pin_ok && !FIXED_MASK[f_d1[5:0]];
    wire       f_w_out  = f_cmd && f_d0 == CMD_DIG_IO && f_n >= 3 && f_pin_ok && !f_is_in;
    wire       f_w_rst  = f_cmd && f_d0 == CMD_DIG_RST && f_n >= 2 && f_pin_ok;
    wire       f_w_time = f_cmd && f_d0 == CMD_PTIME_RD && f_n >= 2 && f_dev_ok && TIMER_MASK[f_dp] &&
                          f_dev_in && !f_busy[f_dp];
    wire       f_hb_ans = f_cmd && f_d0 == CMD_HB && f_n >= 2 &&
                          (f_d1 == HB_UP + HB_ANSWER_OFFSET || f_d1 == HB_DOWN + HB_ANSWER_OFFSET);
    wire       f_acted  = f_w_cfg || f_w_out || f_w_rst || f_w_time;
    wire       f_rflx   = f_cmd && f_d0 == CMD_DIG_IO && f_n == 2 && f_dev_in && f_d1[6];

    reg        f_rep;
    reg [3:0]  f_rep_n;
    reg [31:0] f_rep_data;
    reg [3:0]  f_cmp;    // reply bytes to compare: the first min(N, 4)
    always @(*) begin
        f_rep = 1'b0; f_rep_n = 4'd0; f_rep_data = 32'd0;
        if (f_kind == KIND_PROBE) begin
            f_rep = 1'b1;
        end else if (f_kind == KIND_SERIAL) begin
            f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_SERIAL_ERROR, 16'd0};
        end else if (f_d0 == CMD_HB) begin
            f_rep = 1'b0;
        end else if (!f_valid_code) begin
            f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_CMD_INVALID, 16'd0};
        end else if (f_d0 == CMD_RESET) begin
            f_rep = 1'b0;  // the reset's power-up message answers it
        end else if (f_d0 == CMD_DEBUG) begin
            f_rep = 1'b1; f_rep_n = f_n; f_rep_data = {CMD_DEBUG, f_d1, f_d2, f_tail[39:32]};
        end else if (f_n == 4'd1) begin
            f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_CMD_TOO_SHORT, 16'd0};
        end else if (f_acted) begin
            if (f_n > ((f_d0 == CMD_DIG_CFG || f_d0 == CMD_DIG_IO) ? 4'd3 : 4'd2)) begin
                f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_CMD_TOO_LONG, 16'd0};
            end
        end else if (f_d0 == CMD_DIG_CFG) begin
            f_rep = 1'b1; f_rep_n = 4'd2;
            if (!f_pin_ok) f_rep_data = {CMD_MSG, MSG_CMD_INDEX_ERR, 16'd0};
            else if (f_n == 4'd2) begin
                f_rep_n = 4'd3;
                f_rep_data = {CMD_DIG_CFG, f_d1, FIXED_MASK[f_d1[5:0]], 2'b00, f_pin_cfg, 8'd0};
            end else f_rep_data = {CMD_MSG, MSG_CONFIG_ERR, 16'd0};
        end else if (f_d0 == CMD_DIG_IO) begin
            if (f_n != 4'd2 || !f_dev_in) begin
                f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_CMD_INDEX_ERR, 16'd0};
            end else if (f_d1[7]) begin
                f_rep = 1'b1; f_rep_n = 4'd3;
                f_rep_data = {CMD_DEV_VAL, 2'b00, PIN_ID_BASE[5:0] + f_dp, 7'd0, f_level[f_dp], 8'd0};
            end
        end else if (f_d0 == CMD_DIG_RST) begin
            f_rep = 1'b1; f_rep_n = 4'd2; f_rep_data = {CMD_MSG, MSG_CMD_INDEX_ERR, 16'd0};
        end else begin  // PTIME_RD without a start
            f_rep = 1'b1; f_rep_n = 4'd2;
            if (!f_dev_ok || !TIMER_MASK[f_dp] || !f_dev_in) f_rep_data = {CMD_MSG, MSG_CMD_INDEX_ERR, 16'd0};
            else f_rep_data = {CMD_MSG, MSG_TMR_CONFLICT, 16'd0};
        end
        f_cmp = f_rep_n > 4'd4 ? 4'd4 : f_rep_n;
    end

    integer f_i;
    localparam [NUM_PINS-1:0] F_ONE = 1;
    // d3..d(N-1) of the captured packet's tail (d3 in the top byte).
    wire [39:0] f_tmask = f_n > 4'd3 ? ~(40'hFFFFFFFFFF >> (8 * (f_n - 4'd3))) : 40'd0;
    always @(*) begin
        if (!f_past_valid) assume(rst);
        // Packets at least three clocks apart, as the parser hands them over.
        if (pkt_valid_i) begin
            assume(!f_s2 && !f_p2);
            assume(pkt_kind_i != 2'd3);
            assume(pkt_cmd_i == {|f_cmdf, f_cmdf});
            if (pkt_kind_i == KIND_CMD) assume(pkt_n_i >= 4'd1 && pkt_n_i <= 4'd8);
            if (pkt_kind_i == KIND_PROBE) assume(pkt_n_i == 4'd0);
        end
        if (f_s2) assume((pkt_tail_i & f_tmask) == (f_tail & f_tmask));
        // (d1 only for N >= 2: after a one-byte packet the parser's d1 slot takes the next byte)
        if (f_s2 && f_n >= 4'd2) assume(pkt_d1_i == f_d1);
        assume(pkt_sel_i == F_ONE << pkt_d1_i[5:0]);

        if (f_past_valid) begin
            assert(s2_valid_o == f_s2);
            if (s2_valid_o) assert(!f_s2_q);
            assert((timer_start_o & (timer_start_o - 1'b1)) == {NUM_PINS{1'b0}});
            assert(timer_go_o == (timer_start_o != {NUM_PINS{1'b0}}));
            assert((pin_sel_o & (pin_sel_o - 1'b1)) == {NUM_PINS{1'b0}});
            assert((rearm_o & (rearm_o - 1'b1)) == {NUM_PINS{1'b0}});
            if (!f_s2) begin
                assert(!cfg_we_o && !out_we_o && !hb_answer_o && !reply_o && !dio_rflx_o && !soft_reset_o);
                assert(rearm_o == {NUM_PINS{1'b0}} && timer_start_o == {NUM_PINS{1'b0}});
            end else begin
                assert(cfg_we_o == f_w_cfg);
                assert(out_we_o == f_w_out);
                if (cfg_we_o) assert(cfg_wdata_o == f_d2[4:0]);
                if (out_we_o) assert(out_wdata_o == (f_d2 != 8'd0));
                for (f_i = 0; f_i < NUM_PINS; f_i = f_i + 1) begin
                    assert(rearm_o[f_i] == ((f_w_cfg || f_w_rst) && f_d1 == f_i));
                    if (cfg_we_o || out_we_o) assert(pin_sel_o[f_i] == (f_d1 == f_i));
                    assert(timer_start_o[f_i] == (f_w_time && f_dp == f_i));
                end
                if (timer_start_o != {NUM_PINS{1'b0}})
                    assert(timer_host_o == f_d1[7] && timer_rflx_o == f_d1[6] && timer_idx_o == f_tnum);
                assert(hb_answer_o == f_hb_ans);
                assert(soft_reset_o == f_reset);
                if (hb_answer_o) assert(hb_answer_down_o == f_d1[0]);
                assert(reply_o == f_rep);
                if (reply_o) begin
                    assert(reply_n_o == f_rep_n);
                    assert(reply_n_o <= 4'd8);
                    for (f_i = 0; f_i < 4; f_i = f_i + 1)
                        if (f_i < f_cmp) assert(reply_data_o[31-8*f_i -: 8] == f_rep_data[31-8*f_i -: 8]);
                    if (f_kind == KIND_CMD && f_d0 == CMD_DEBUG)  // (d4..d(N-1): the slot sends N bytes)
                        assert((reply_tail_o & f_tmask[31:0]) == (f_tail[31:0] & f_tmask[31:0]));
                end
                assert(dio_rflx_o == f_rflx);
                if (dio_rflx_o) assert(dio_id_o == PIN_ID_BASE[5:0] + f_dp && dio_val_o == f_level[f_dp]);
            end
        end
    end

    // Covers: a configuration write, an output write, a timer start with RFLX delivery, a
    // DIG_IO value to RFLX and the host, cmdTooLong after an action, an 8-byte echo, a
    // heartbeat answer; three packets at the closest spacing (3 clocks).
    reg [1:0] f_npkt = 2'd0;
    reg [2:0] f_gap  = 3'd0;
    always @(posedge clk) begin
        if (f_gap != 3'd7) f_gap <= f_gap + 3'd1;
        if (pkt_valid_i) begin
            f_gap <= 3'd1;
            f_npkt <= (f_npkt == 2'd0 || f_gap == 3'd3) ? (f_npkt == 2'd3 ? 2'd3 : f_npkt + 2'd1) : 2'd1;
        end
        if (rst) begin
            f_npkt <= 2'd0;
            f_gap  <= 3'd0;
        end
    end
    always @(*) if (f_past_valid && !rst) begin
        cover(cfg_we_o);
        cover(out_we_o);
        cover(timer_start_o != {NUM_PINS{1'b0}} && timer_rflx_o);
        cover(soft_reset_o);
        cover(dio_rflx_o && reply_o);
        cover(f_acted && f_s2 && reply_o && reply_data_o[23:16] == MSG_CMD_TOO_LONG);
        cover(reply_o && reply_n_o == 4'd8 && reply_data_o[31:24] == CMD_DEBUG);
        cover(hb_answer_o && hb_answer_down_o);
        cover(f_npkt == 2'd3 && s2_valid_o);
    end
