// SPDX-License-Identifier: Apache-2.0
// Formal properties of bsd_parser (included at the end of the module under `ifdef FORMAL).
// Inputs: AXI-Stream source (a byte offered stays offered, unchanged, until taken), hold_i
// and tick_i free, reset on the first clock. A reference parser written from PROTOCOL.md §2
// (address, N, N data bytes; own address with 1 <= N <= 8 is a command, own address with
// N > 8 is serialError, 0xAD with N = 0 the probe, anything else consumed; a partial packet
// dropped after TIMEOUT_TICKS idle ticks) runs on the accepted bytes. Asserted:
// - pkt_valid_o exactly when the reference completes a packet that needs action: a command
//   the clock after its last byte, a probe or serialError the first clock hold_i is 0 after
//   its length byte; its kind, N and data bytes d0..d(N-1) are the packet's; a command's N is
//   the length byte it accepted, 1..8 (N > 8 never reaches the executor as a command);
//   pkt_valid_o never follows a clock with hold_i 1 or with pkt_valid_o, nor comes with
//   s_axis_tready waiting for hold_i (so the top's hold_i need not include pkt_valid_o:
//   bsd_reply_slot assumes packets at least two clocks apart);
// - pkt_sel_o is pkt_d1_o's bits 5:0 as a one-hot over NUM_PINS pins (0 past the last) on
//   every clock after the first load (they load together; bsd_exec's props assume it), and a
//   command's data bytes d0..d(N-1), and with N >= 2 pkt_sel_o, are unchanged on the clock
//   after its handover (stage 2 reads them there; a slot past N may take the next byte);
// - pkt_cmd_o is pkt_d0_o's command flags, from the second clock after reset on (the two
//   load together; the first load comes on the clock after reset, which sets every slot);
// - from any reachable state, at most 10 bytes (address included) or TIMEOUT_TICKS idle
//   ticks (tready 1, tvalid 0) bring the parser back to waiting for an address;
// - s_axis_tready exact: 0 only in reset, or with hold_i while a probe/serialError waits to be
//   handed over or the next byte is the last of a command;
// - induction: the design's registers agree with the reference.
    localparam integer TW = $clog2(TIMEOUT_TICKS + 1);  // the idle tick count's width
    reg         f_past_valid = 1'b0;
    reg         f_rst_q, f_sv_q, f_sr_q, f_hold_q, f_pv_q;
    reg  [7:0]  f_sd_q;
    wire        f_acc = s_axis_tvalid && s_axis_tready;
    wire [7:0]  f_b = s_axis_tdata;
    // The reference parser.
    localparam [1:0] F_ADDR = 2'd0, F_LEN = 2'd1, F_DATA = 2'd2;
    reg  [1:0]  f_st;
    reg  [7:0]  f_addr, f_len;
    reg  [3:0]  f_cnt;        // data bytes taken
    reg  [63:0] f_dv;         // the data bytes, d0 in the top byte
    reg         f_pend;       // a probe / serialError waits to be handed over
    reg         f_exp;        // pkt_valid_o expected now
    reg  [1:0]  f_pk;         // its kind
    reg  [3:0]  f_pn;         // its N (low 4 bits)
    reg  [TW-1:0] f_idle;     // idle ticks in LEN / DATA since the last byte
    // Port-level counters: bytes since the design last waited for an address, idle ticks
    // since the last byte.
    reg  [3:0]  f_nb;
    reg  [3:0]  f_tk;
    reg         f_ld = 1'b0;  // pkt_d0_q and pkt_cmd_q have been loaded
    reg         f_ld1 = 1'b0; // pkt_d1_q and pkt_sel_q have been loaded
    wire [6:0]  f_cmdf = {pkt_d0_o == CMD_PTIME_RD, pkt_d0_o == CMD_DIG_RST, pkt_d0_o == CMD_DIG_IO,
                          pkt_d0_o == CMD_DIG_CFG, pkt_d0_o == CMD_RESET, pkt_d0_o == CMD_DEBUG,
                          pkt_d0_o == CMD_HB};
    wire        f_own  = f_addr == ADDR_OWN;
    wire        f_lastc = f_st == F_DATA && f_own && ({4'd0, f_cnt} + 8'd1 == f_len);
    wire        f_wait = s_axis_tready && !s_axis_tvalid && f_st != F_ADDR;
    wire        f_tmo  = (RX_TIMEOUT_US != 0) && f_wait && tick_i &&
                         f_idle == TIMEOUT_TICKS[TW-1:0] - 1'b1;
    wire        f_addr_wait = !len_q && !data_q;
    integer     f_i;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata;
        f_hold_q <= hold_i;
        f_pv_q   <= pkt_valid_o && !rst;
        f_pd_q   <= f_pd;
        f_sel_q  <= pkt_sel_o;
        if (pos_q[0]) f_ld <= 1'b1;
        if (pos_q[1]) f_ld1 <= 1'b1;
        f_exp <= 1'b0;
        if (f_pend && !hold_i) begin
            f_pend <= 1'b0;
            f_exp  <= 1'b1;
        end
        if (f_acc) f_idle <= {TW{1'b0}};
        else if (f_wait && tick_i) f_idle <= f_idle + 1'b1;
        if (f_tmo) begin
            f_st <= F_ADDR;
        end else if (f_acc) begin
            case (f_st)
                F_ADDR: begin
                    f_addr <= f_b;
                    f_st   <= F_LEN;
                end
                F_LEN: begin
                    f_len <= f_b;
                    f_cnt <= 4'd0;
                    if (f_b == 8'd0 || f_b > 8'd8) begin
                        f_st <= F_ADDR;
                        if (f_own && f_b > 8'd8) begin
                            f_pend <= 1'b1; f_pk <= KIND_SERIAL; f_pn <= f_b[3:0];
                        end
                        if (f_addr == ADDR_RESYNC && f_b == 8'd0) begin
                            f_pend <= 1'b1; f_pk <= KIND_PROBE; f_pn <= 4'd0;
                        end
                    end else begin
                        f_st <= F_DATA;
                    end
                end
                default: begin
                    f_dv  <= f_dv & ~(64'hFF << (8 * (7 - f_cnt))) | ({56'd0, f_b} << (8 * (7 - f_cnt)));
                    f_cnt <= f_cnt + 4'd1;
                    if ({4'd0, f_cnt} + 8'd1 == f_len) begin
                        f_st <= F_ADDR;
                        if (f_own) begin
                            f_exp <= 1'b1; f_pk <= KIND_CMD; f_pn <= f_len[3:0];
                        end
                    end
                end
            endcase
        end
        if (f_acc) f_nb <= f_addr_wait ? 4'd1 : (f_nb == 4'd15 ? 4'd15 : f_nb + 4'd1);
        if (f_acc) f_tk <= 4'd0;
        else if (s_axis_tready && !s_axis_tvalid && tick_i && f_tk != 4'd15) f_tk <= f_tk + 4'd1;
        if (rst) begin
            f_st <= F_ADDR; f_addr <= 8'd0; f_pend <= 1'b0; f_exp <= 1'b0;
            f_idle <= {TW{1'b0}}; f_nb <= 4'd0; f_tk <= 4'd0;
        end
    end

    // The handed-over packet's data bytes, as the design presents them.
    wire [63:0] f_pd = {pkt_d0_o, pkt_d1_o, pkt_d2_o, pkt_tail_o};
    wire [63:0] f_mask = ~(64'hFFFFFFFFFFFFFFFF >> (8 * f_pn));  // the first N bytes (N <= 8)
    reg  [63:0] f_pd_q;
    reg  [NUM_PINS-1:0] f_sel_q;
    wire [63:0] f_cmask = ~(64'hFFFFFFFFFFFFFFFF >> (8 * f_cnt)); // the bytes taken so far

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && f_sv_q && !f_sr_q) begin
            assume(s_axis_tvalid);
            assume(s_axis_tdata == f_sd_q);
        end
        if (f_ld1) assert(pkt_sel_o == SEL_ONE << pkt_d1_o[5:0]);
        // The handed-over command's bytes hold through stage 2.
        if (f_past_valid && !f_rst_q && f_pv_q && f_pk == KIND_CMD) begin
            assert((f_pd & f_mask) == (f_pd_q & f_mask));
            if (f_pn >= 4'd2) assert(pkt_sel_o == f_sel_q);
        end
        if (f_past_valid && !f_rst_q) begin
            // Handover: exactly the reference's packets, with their kind, N and bytes.
            assert(pkt_valid_o == f_exp);
            if (pkt_valid_o) begin
                assert(!f_hold_q);
                // Never waiting on the handover's clock, and never two handovers in a
                // row: the top gives hold_i the reply slot's flop alone (bsd_reply_slot
                // hold_o), without this clock's pkt_valid.
                assert(!stop_q);
                assert(!f_pv_q);
                assert(pkt_kind_o == f_pk && pkt_n_o == f_pn);
                if (pkt_kind_o == KIND_CMD) begin
                    assert(f_len >= 8'd1 && f_len <= 8'd8 && {4'd0, pkt_n_o} == f_len);
                    assert((f_pd & f_mask) == (f_dv & f_mask));
                end
            end
            // d0's command flags.
            assert(f_ld);
            assert(pkt_cmd_o == {|f_cmdf, f_cmdf});
            // Back to waiting for an address within 10 bytes or TIMEOUT_TICKS idle ticks.
            if (!f_addr_wait) begin
                assert(f_nb >= 4'd1 && f_nb <= 4'd9);
                if (RX_TIMEOUT_US != 0) assert(f_tk < TIMEOUT_TICKS);
            end
            // s_axis_tready exact.
            assert(s_axis_tready == (!rst && !(hold_i && (f_pend || f_lastc))));
            // Induction: the design agrees with the reference.
            assert(f_st != 2'd3);
            assert(f_addr_wait == (f_st == F_ADDR));
            assert(pend_q == f_pend && !(pend_q && (len_q || data_q)) && !(len_q && data_q));
            assert(len_q == (f_st == F_LEN) && data_q == (f_st == F_DATA));
            assert(stop_q == (f_pend || f_lastc));
            if (f_pend) begin
                assert(pkt_kind_q == f_pk && pkt_n_q == f_pn);
                if (f_pk == KIND_SERIAL) assert(f_own && f_len > 8'd8 && f_pn == f_len[3:0]);
                else assert(f_pk == KIND_PROBE && f_addr == ADDR_RESYNC && f_len == 8'd0 && f_pn == 4'd0);
            end
            if (f_st != F_ADDR) begin
                assert(own_q == f_own && probe_q == (f_addr == ADDR_RESYNC));
                assert(idle_q == lfsr_pow({{(32-TW){1'b0}}, f_idle}, LW, LFSR_P) && f_idle < TIMEOUT_TICKS &&
                       f_tk == {1'b0, f_idle});
            end
            if (f_st == F_LEN) assert(f_nb == 4'd1);
            if (f_st == F_DATA) begin
                assert(f_len >= 8'd1 && f_len <= 8'd8 && {4'd0, f_cnt} < f_len);
                assert(f_nb == f_cnt + 4'd2);
                assert(pos_q == 8'd1 << f_cnt && pkt_n_q == f_len[3:0] && pkt_kind_q == KIND_CMD);
                assert({1'b0, rem_q} == f_len[3:0] - 4'd1 - f_cnt);
                assert(last_q == ({4'd0, f_cnt} + 8'd1 == f_len));
                assert((f_pd & f_cmask) == (f_dv & f_cmask));
            end
        end
    end

    reg f_tmo_q;
    always @(posedge clk) f_tmo_q <= f_tmo && !rst;
    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(pkt_valid_o && pkt_kind_o == KIND_CMD && pkt_n_o == 4'd8);   // an 8-byte command
        cover(pkt_valid_o && pkt_kind_o == KIND_CMD && pkt_n_o == 4'd1);   // a 1-byte command
        cover(pkt_valid_o && pkt_kind_o == KIND_SERIAL);                  // N > 8 to this module
        cover(pkt_valid_o && pkt_kind_o == KIND_PROBE);                   // the resync probe
        cover(f_tmo_q && f_st == F_ADDR);                                 // a partial packet timed out
        cover(f_acc && f_st == F_DATA && !f_own && {4'd0, f_cnt} + 8'd1 == f_len);  // another module's packet consumed
        cover(f_acc && f_st == F_LEN && f_own && f_b == 8'd0);            // N = 0 to this module: nothing
        cover(s_axis_tvalid && !s_axis_tready && f_lastc);                // a command's last byte held
        cover(s_axis_tvalid && !s_axis_tready && f_pend);                 // a byte held behind a waiting probe
    end
