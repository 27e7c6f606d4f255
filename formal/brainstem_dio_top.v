// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Formal wrapper of brainstem_dio for formal/brainstem_dio.sby: a small build (one pin with
// a timer, 2 MHz clock: a 1.6 us tick every 3.2 clocks, latches sampled every clock, a
// 4 us inter-byte timeout, no heartbeat) and properties on the top's ports only. The
// blocks' own props files are not read (the RTL is read without -formal), so none of their
// input assumptions constrain the core here.
// Assumed: reset on the first clock (and free after it); the host side obeys AXI-Stream
// (a byte offered stays offered, unchanged, until taken); m_axis_tready, pin_i free.
// Asserted:
// - m_axis: tvalid held until tready, tdata and tlast unchanged while stalled;
// - every packet out is `A, N, d0 .. d(N-1)` with N <= 8 and tlast exactly on its byte
//   N + 2 (tlast never on the address byte, on the N byte exactly when N = 0);
// - the first packet after reset is the power-up message `A, 2, 0x80, 4`;
// - with m_axis_tready 1 on every clock since reset, s_axis_tready is never 0 for more
//   than F_STALL_MAX clocks in a row (outside reset);
// - rflx_valid is a one-clock strobe per value: two strobes on consecutive clocks carry
//   different device IDs (a value is never strobed twice).
// With F_RESET (the reset task; no RX timeout, so the host-side framing below is exact),
// cmdRESET: the reset takes effect 3 clocks after the command's last byte; a packet with a
// byte taken by then is finished, and the next packet out is the power-up message (the
// offered first byte of a packet with none taken included); the clock after the reset
// every pin is an input again and no RFLX strobe comes.
module brainstem_dio_top (
    input  wire       clk,
    input  wire       rst,
    input  wire [7:0] s_axis_tdata,
    input  wire       s_axis_tvalid,
    input  wire       m_axis_tready,
    input  wire [0:0] pin_i
);
    localparam [7:0] A = 8'd2;
    // The stall bound with the sink always ready. s_axis_tready is 0 only while the parser
    // holds a byte (a command's last byte, or the byte after a probe / N > 8 length byte)
    // and hold is 1, i.e. from the previous packet's handover until its reply has left. A
    // byte is held at the earliest 3 clocks after the previous packet's last byte (two more
    // bytes must come first), the clock the previous reply is requested (r). That reply
    // leaves behind at most one older packet: the timer's (one pin, no heartbeat), 6 bytes,
    // whose first byte is out by r + 3; then the reply's own 10 bytes at most (cmdDEBUG,
    // N = 8): its last byte leaves by r + 18, the hold clears on r + 19. So at most 19
    // clocks in a row (with NUM_PINS timers and a heartbeat: 3 + 6 * timers + 4 + 10).
    localparam integer F_STALL_MAX = 19;
`ifdef F_RESET
    localparam integer F_RX_TIMEOUT_US = 0;
`else
    localparam integer F_RX_TIMEOUT_US = 4;
`endif

    wire       s_axis_tready;
    wire [7:0] m_axis_tdata;
    wire       m_axis_tvalid, m_axis_tlast;
    wire [0:0] pin_o, pin_oe, raw_trans;
    wire       rflx_valid, link_up;
    wire [5:0] rflx_id;
    wire [15:0] rflx_data;

    brainstem_dio #(
        .CLK_HZ        (2_000_000),
        .MODULE_ADDR   (2),
        .NUM_PINS      (1),
        .TIMER_MASK    (1'b1),
        .FIXED_MASK    (1'b0),
        .FIXED_CFG     (8'd0),
        .PIN_ID_BASE   (5),
        .TIMER_ID_BASE (10),
        .TRANS_ID_BASE (15),
        .POLL_HZ       (0),
        .RX_TIMEOUT_US (F_RX_TIMEOUT_US),
        .HB_RATE       (0)
    ) dut (
        .clk(clk), .rst(rst),
        .s_axis_tdata(s_axis_tdata), .s_axis_tvalid(s_axis_tvalid), .s_axis_tready(s_axis_tready),
        .m_axis_tdata(m_axis_tdata), .m_axis_tvalid(m_axis_tvalid), .m_axis_tready(m_axis_tready),
        .m_axis_tlast(m_axis_tlast),
        .pin_i(pin_i), .pin_o(pin_o), .pin_oe(pin_oe), .raw_trans(raw_trans),
        .rflx_valid(rflx_valid), .rflx_id(rflx_id), .rflx_data(rflx_data), .link_up(link_up)
    );

    reg        f_past_valid = 1'b0;
    reg        f_rst_q, f_sv_q, f_sr_q, f_mv_q, f_mr_q, f_ml_q, f_rv_q;
    reg  [7:0] f_sd_q, f_md_q;
    reg  [5:0] f_rid_q;
    reg  [3:0] f_idx;        // bytes of the current packet already taken (saturating)
    reg  [7:0] f_n;          // its N
    reg        f_mr_all;     // m_axis_tready 1 on every clock since reset
    reg  [5:0] f_stall;      // clocks in a row with s_axis_tready 0 (outside reset)
    reg  [3:0] f_pkts;       // packets out (saturating)
    reg  [5:0] f_stall_max;  // the longest stall so far (for the covers)
    wire       f_mhs = m_axis_tvalid && m_axis_tready;
    wire       f_shs = s_axis_tvalid && s_axis_tready;

    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_q <= rst;
        f_sv_q <= s_axis_tvalid; f_sr_q <= s_axis_tready; f_sd_q <= s_axis_tdata;
        f_mv_q <= m_axis_tvalid; f_mr_q <= m_axis_tready; f_md_q <= m_axis_tdata;
        f_ml_q <= m_axis_tlast;
        f_rv_q <= rflx_valid; f_rid_q <= rflx_id;
        if (f_mhs) begin
            f_idx <= m_axis_tlast ? 4'd0 : (f_idx == 4'd15 ? 4'd15 : f_idx + 4'd1);
            if (f_idx == 4'd1) f_n <= m_axis_tdata;
            if (m_axis_tlast && f_pkts != 4'd15) f_pkts <= f_pkts + 4'd1;
        end
        if (!m_axis_tready) f_mr_all <= 1'b0;
        if (!s_axis_tready && f_stall != 6'd63) f_stall <= f_stall + 6'd1;
        if (s_axis_tready) f_stall <= 6'd0;
        if (f_stall > f_stall_max) f_stall_max <= f_stall;
        if (rst) begin
            f_idx <= 4'd0;
            f_mr_all <= 1'b1;
            f_stall <= 6'd0;
            f_pkts <= 4'd0;
            f_stall_max <= 6'd0;
        end
    end

    always @(*) begin
        if (!f_past_valid) assume(rst);
        if (f_past_valid && !f_rst_q && f_sv_q && !f_sr_q) begin
            assume(s_axis_tvalid);
            assume(s_axis_tdata == f_sd_q);
        end
        if (f_past_valid && !f_rst_q && !rst) begin
            // m_axis AXI-Stream.
            if (f_mv_q && !f_mr_q) begin
                assert(m_axis_tvalid);
                assert(m_axis_tdata == f_md_q);
                assert(m_axis_tlast == f_ml_q);
            end
            // Packet framing: A, N (<= 8), N bytes, tlast on byte N + 2.
            if (m_axis_tvalid) begin
                if (f_idx == 4'd0) assert(m_axis_tdata == A && !m_axis_tlast);
                if (f_idx == 4'd1) assert(m_axis_tdata <= 8'd8 && m_axis_tlast == (m_axis_tdata == 8'd0));
                if (f_idx >= 4'd2) assert(f_n <= 8'd8 && m_axis_tlast == ({4'd0, f_idx} == f_n + 8'd1));
            end
            // The first packet is the power-up message A, 2, 0x80, statePowerReset.
            if (m_axis_tvalid && f_pkts == 4'd0 && f_idx <= 4'd3)
                assert(m_axis_tdata == (f_idx == 4'd0 ? A : f_idx == 4'd1 ? 8'd2 :
                                        f_idx == 4'd2 ? 8'h80 : 8'd4));
            // The input stall bound with the sink always ready.
            if (f_mr_all) assert(f_stall <= F_STALL_MAX);
            // RFLX: one strobe per value.
            if (rflx_valid && f_rv_q) assert(rflx_id != f_rid_q);
        end
    end

`ifdef F_RESET
    // The host's packets as the parser frames them, and the clocks since the last byte of
    // a cmdRESET (f_since 3 = the reset's clock).
    reg  [1:0] f_hst;        // 0 address, 1 length, 2 data
    reg        f_hown, f_hd0_seen;
    reg  [3:0] f_hleft;
    reg  [7:0] f_hd0;
    reg  [2:0] f_since;      // 0: no cmdRESET yet; saturates at 7
    reg        f_pu;         // the power-up message is due
    reg        f_keep;       // a packet partly sent at the reset is still going out
    wire [7:0] f_hd0_now = f_hd0_seen ? f_hd0 : s_axis_tdata;
    wire       f_rcmd = f_shs && f_hst == 2'd2 && f_hleft == 4'd1 && f_hown && f_hd0_now == 8'd24;
    always @(posedge clk) begin
        if (f_shs) begin
            case (f_hst)
                2'd0: begin
                    f_hown <= s_axis_tdata == A;
                    f_hst  <= 2'd1;
                end
                2'd1: begin
                    f_hleft    <= s_axis_tdata[3:0];
                    f_hd0_seen <= 1'b0;
                    f_hst      <= (s_axis_tdata == 8'd0 || s_axis_tdata > 8'd8) ? 2'd0 : 2'd2;
                end
                default: begin
                    if (!f_hd0_seen) f_hd0 <= s_axis_tdata;
                    f_hd0_seen <= 1'b1;
                    f_hleft    <= f_hleft - 4'd1;
                    if (f_hleft == 4'd1) f_hst <= 2'd0;
                end
            endcase
        end
        if (f_rcmd) f_since <= 3'd1;
        else if (f_since != 3'd0 && f_since != 3'd7) f_since <= f_since + 3'd1;
        if (f_since == 3'd3) begin
            f_pu   <= 1'b1;
            f_keep <= m_axis_tvalid && (f_idx != 4'd0 || m_axis_tready) && !(f_mhs && m_axis_tlast);
        end else begin
            if (f_keep && f_mhs && m_axis_tlast) f_keep <= 1'b0;
            if (f_pu && !f_keep && f_mhs && m_axis_tlast) f_pu <= 1'b0;
        end
        if (rst) begin
            f_hst   <= 2'd0;
            f_since <= 3'd0;
            f_pu    <= 1'b0;
            f_keep  <= 1'b0;
        end
    end

    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        if (f_pu && !f_keep && f_since != 3'd3 && m_axis_tvalid)
            assert(m_axis_tdata == (f_idx == 4'd0 ? A : f_idx == 4'd1 ? 8'd2 :
                                    f_idx == 4'd2 ? 8'h80 : 8'd4));
        if (f_since == 3'd4) begin
            assert(pin_oe == 1'b0);
            assert(!rflx_valid);
        end
        cover(f_pu && f_keep && f_since == 3'd4);                        // a partly sent packet finishes
        cover(f_since == 3'd3 && m_axis_tvalid && f_idx == 4'd0 && !m_axis_tready);  // replaced in place
        cover(f_since == 3'd7 && f_pu && !f_keep && f_mhs && m_axis_tlast);  // the power-up message out
    end
`endif

    always @(*) if (f_past_valid && !rst && !f_rst_q) begin
        cover(f_mhs && m_axis_tlast && f_pkts == 4'd1);                 // a reply after the power-up message
        cover(f_mhs && m_axis_tlast && f_idx == 4'd9);                   // a 10-byte reply (cmdDEBUG, N = 8)
        cover(rflx_valid);                                               // an RFLX strobe
        cover(f_mv_q && !f_mr_q && f_idx == 4'd2);                       // m_axis stalled mid-packet
        cover(f_mr_all && s_axis_tvalid && !s_axis_tready && f_pkts == 4'd1);  // s_axis held behind a reply
    end
endmodule
`default_nettype wire
