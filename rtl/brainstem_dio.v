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

    // Packet sources of bsd_tx: timers 0..NUM_PINS-1 (by pin, so same-clock
    // results leave by ascending pin), then the command reply, then cmdHB.
    localparam integer SRC_REPLY = NUM_PINS;
    localparam integer SRC_HB    = NUM_PINS + 1;
    localparam integer K         = NUM_PINS + 2;

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
    function integer highest_timer_pin(input integer unused);
        integer q;
        begin
            highest_timer_pin = -1;
            for (q = 0; q < NUM_PINS; q = q + 1)
                if (TIMER_MASK[q]) highest_timer_pin = q;
        end
    endfunction

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
    // finishes a packet already partly sent (bsd_tx, flush_i).
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

    // Arms every latch two clocks after reset, once the synchronizer holds
    // real pad levels (a fixed ENA pin is armed from power-up).
    reg [1:0] init_q;
    always @(posedge clk) begin
        init_q <= {init_q[0], 1'b0};
        if (core_rst) init_q <= 2'b11;
    end
    wire init_arm = |init_q;

    // -------------------------------------------------------------- parsing
    wire       slot_hold;
    // The clock of the reset itself holds too: a packet handed over then
    // would meet the reply slot as the reset fills it with the power-up message.
    wire       pkt_hold = slot_hold || soft_rst_q;
    wire       pkt_valid;
    wire [1:0] pkt_kind;
    wire [3:0] pkt_n;
    wire [7:0] pkt_d0, pkt_d1, pkt_d2;
    wire [39:0] pkt_tail;

    bsd_parser #(.MODULE_ADDR(MODULE_ADDR), .RX_TIMEOUT_US(RX_TIMEOUT_US)) u_parser (
        .clk           (clk),
        .rst           (rst),
        .tick_i        (tick),
        .hold_i        (pkt_hold),
        .s_axis_tdata  (s_axis_tdata),
        .s_axis_tvalid (s_axis_tvalid),
        .s_axis_tready (s_axis_tready),
        .pkt_valid_o   (pkt_valid),
        .pkt_kind_o    (pkt_kind),
        .pkt_n_o       (pkt_n),
        .pkt_d0_o      (pkt_d0),
        .pkt_d1_o      (pkt_d1),
        .pkt_d2_o      (pkt_d2),
        .pkt_tail_o    (pkt_tail)
    );

    // ------------------------------------------------------------ execution
    wire [5*NUM_PINS-1:0] cfg;
    wire [NUM_PINS-1:0]   out_latch;
    wire [NUM_PINS-1:0]   timer_busy;
    wire                  cfg_we, out_we;
    wire [5:0]            wr_pin_idx;
    wire [4:0]            cfg_wdata;
    wire                  out_wdata;
    wire [NUM_PINS-1:0]   rearm;
    wire [NUM_PINS-1:0]   timer_start;
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
        .PIN_ID_BASE (PIN_ID_BASE)
    ) u_exec (
        .clk             (clk),
        .rst             (core_rst),
        .pkt_valid_i     (pkt_valid),
        .pkt_kind_i      (pkt_kind),
        .pkt_n_i         (pkt_n),
        .pkt_d0_i        (pkt_d0),
        .pkt_d1_i        (pkt_d1),
        .pkt_d2_i        (pkt_d2),
        .pkt_tail_i      (pkt_tail),
        .cfg_i           (cfg),
        .level_i         (level),
        .timer_busy_i    (timer_busy),
        .cfg_we_o        (cfg_we),
        .out_we_o        (out_we),
        .pin_idx_o       (wr_pin_idx),
        .cfg_wdata_o     (cfg_wdata),
        .out_wdata_o     (out_wdata),
        .rearm_o         (rearm),
        .timer_start_o   (timer_start),
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
    wire                  dio_rflx_req, dio_rflx_val, dio_rflx_done;
    wire [5:0]            dio_rflx_id;
    wire [NUM_PINS-1:0]   dio_rflx_below;

    bsd_reply_slot #(.NUM_PINS(NUM_PINS), .TIMER_ID_BASE(TIMER_ID_BASE)) u_slot (
        .clk          (clk),
        .rst          (core_rst),
        .pkt_valid_i  (pkt_valid),
        .s2_valid_i   (s2_valid),
        .reply_i      (s2_reply),
        .reply_n_i    (s2_reply_n),
        .reply_data_i (s2_reply_data),
        .reply_tail_i (s2_reply_tail),
        .dio_rflx_i   (s2_dio_rflx),
        .dio_id_i     (s2_dio_id),
        .dio_val_i    (s2_dio_val),
        .hold_o       (slot_hold),
        .rep_req_o    (rep_req),
        .rep_n_o      (rep_n),
        .rep_data_o   (rep_data),
        .rep_tail_o   (rep_tail),
        .rep_done_i   (rep_done),
        .dio_req_o    (dio_rflx_req),
        .dio_id_o     (dio_rflx_id),
        .dio_val_o    (dio_rflx_val),
        .dio_below_o  (dio_rflx_below),
        .dio_done_i   (dio_rflx_done)
    );

    bsd_cfg_regs #(
        .NUM_PINS   (NUM_PINS),
        .FIXED_MASK (FIXED_MASK),
        .FIXED_CFG  (FIXED_CFG)
    ) u_cfg (
        .clk         (clk),
        .rst         (core_rst),
        .cfg_we_i    (cfg_we),
        .out_we_i    (out_we),
        .pin_idx_i   (wr_pin_idx),
        .cfg_wdata_i (cfg_wdata),
        .out_wdata_i (out_wdata),
        .cfg_o       (cfg),
        .out_o       (out_latch)
    );

    // --------------------------------------------------------- per-pin blocks
    wire [NUM_PINS-1:0]    timer_host_req, timer_rflx_req;
    wire [NUM_PINS-1:0]    timer_host_done, timer_rflx_done;
    wire [16*NUM_PINS-1:0] timer_result;

    genvar p;
    generate
        for (p = 0; p < NUM_PINS; p = p + 1) begin : g_pin
            wire [4:0] c = cfg[5*p +: 5];

            assign pin_oe[p] = !c[0];
            assign pin_o[p]  = out_latch[p];

            bsd_trans_latch u_latch (
                .clk      (clk),
                .rst      (core_rst),
                .arm_i    (rearm[p] || init_arm),
                .ena_i    (c[1]),
                .trg_i    (c[2]),
                .input_i  (c[0]),
                .sample_i (poll),
                .level_i  (level[p]),
                .fire_o   (raw_trans[p])
            );

            if (TIMER_MASK[p]) begin : g_timer
                bsd_event_timer u_timer (
                    .clk         (clk),
                    .rst         (core_rst),
                    .tick_i      (tick),
                    .level_i     (level[p]),
                    .start_i     (timer_start[p]),
                    .mode_i      (c[4]),
                    .target_i    (c[3]),
                    .host_i      (timer_host),
                    .rflx_i      (timer_rflx),
                    .host_done_i (timer_host_done[p]),
                    .rflx_done_i (timer_rflx_done[p]),
                    .busy_o      (timer_busy[p]),
                    .host_req_o  (timer_host_req[p]),
                    .rflx_req_o  (timer_rflx_req[p]),
                    .result_o    (timer_result[16*p +: 16])
                );
            end else begin : g_no_timer
                assign timer_busy[p]              = 1'b0;
                assign timer_host_req[p]          = 1'b0;
                assign timer_rflx_req[p]          = 1'b0;
                assign timer_result[16*p +: 16]   = 16'd0;
                // The executor never starts a timer on this pin, and TMODE and
                // TSTATE are only stored here.
                wire unused_no_timer = ^{timer_start[p], timer_host_done[p],
                                         timer_rflx_done[p], c[4:3]};
            end
        end
    endgenerate

    // ----------------------------------------------------------- heartbeat
    wire       hb_req, hb_done;
    wire [7:0] hb_type;

    bsd_heartbeat #(.HB_RATE(HB_RATE)) u_hb (
        .clk           (clk),
        .rst           (core_rst),
        .tick_i        (tick),
        .answer_i      (hb_answer),
        .answer_down_i (hb_answer_down),
        .req_o         (hb_req),
        .type_o        (hb_type),
        .done_i        (hb_done),
        .link_up_o     (link_up)
    );

    // -------------------------------------------------------------- output
    wire [K-1:0]    tx_req;
    wire [3*K-1:0]  tx_n;
    wire [32*K-1:0] tx_data;
    wire [K-1:0]    tx_done;

    generate
        for (p = 0; p < NUM_PINS; p = p + 1) begin : g_tx_timer
            localparam integer ID = TIMER_ID_BASE + p;
            assign tx_req[p]            = timer_host_req[p];
            assign tx_n[3*p +: 3]       = 3'd4;
            assign tx_data[32*p +: 32]  = {CMD_DEV_VAL, ID[7:0], timer_result[16*p +: 16]};
            assign timer_host_done[p]   = tx_done[p];
        end
    endgenerate

    assign tx_req[SRC_REPLY]               = rep_req;
    assign tx_n[3*SRC_REPLY +: 3]          = rep_n[2:0];  // bit 3 and d4..d7: the long ports
    assign tx_data[32*SRC_REPLY +: 32]     = rep_data;
    assign rep_done                        = tx_done[SRC_REPLY];

    assign tx_req[SRC_HB]                  = hb_req;
    assign tx_n[3*SRC_HB +: 3]             = 3'd2;
    assign tx_data[32*SRC_HB +: 32]        = {CMD_HB, hb_type, 16'd0};
    assign hb_done                         = tx_done[SRC_HB];

    bsd_tx #(.MODULE_ADDR(MODULE_ADDR), .K(K), .LONG_SRC(SRC_REPLY), .POWERUP_SRC(SRC_REPLY)) u_tx (
        .clk           (clk),
        .rst           (rst),
        .flush_i       (soft_rst_q),
        .req_i         (tx_req),
        .n_i           (tx_n),
        .data_i        (tx_data),
        .long_n3_i     (rep_n[3]),
        .long_data_i   (rep_tail),
        .done_o        (tx_done),
        .m_axis_tdata  (m_axis_tdata),
        .m_axis_tvalid (m_axis_tvalid),
        .m_axis_tready (m_axis_tready),
        .m_axis_tlast  (m_axis_tlast)
    );

    bsd_rflx_arb #(.NUM_PINS(NUM_PINS), .TIMER_ID_BASE(TIMER_ID_BASE)) u_rflx (
        .clk            (clk),
        .rst            (core_rst),
        .dio_req_i      (dio_rflx_req),
        .dio_id_i       (dio_rflx_id),
        .dio_val_i      (dio_rflx_val),
        .dio_below_i    (dio_rflx_below),
        .dio_done_o     (dio_rflx_done),
        .timer_req_i    (timer_rflx_req),
        .timer_result_i (timer_result),
        .timer_done_o   (timer_rflx_done),
        .rflx_valid_o   (rflx_valid),
        .rflx_id_o      (rflx_id),
        .rflx_data_o    (rflx_data)
    );
endmodule
`default_nettype wire
