// SPDX-License-Identifier: Apache-2.0
`default_nettype none
// Executes one packet from the parser in two clocks. The first looks up the
// addressed pin's state (a wide mux on many-pin builds) and decides the
// state changes (configuration and output writes, re-arms, timer starts, the
// heartbeat answer) into registers, so that those strobes leave this module
// straight from flops. The second drives them and decides the reply or
// message with the contract's precedence (cmdInvalid, cmdTooShort, the
// command's own error, then the action and cmdTooLong), and whether a DIG_IO
// read sends its value on RFLX. Packets come at least three clocks apart, so
// the stages never overlap. cmdDEBUG's echo takes d3..d7 straight from the
// parser's registers in stage 2: the parser writes no data byte before the
// clock after stage 2, when the reply slot has taken them. The decision goes to bsd_reply_slot, which holds
// the waiting reply and the waiting DIG_IO RFLX value and tells the parser
// when to hold.
module bsd_exec #(
    parameter integer        NUM_PINS    = 5,
    parameter [NUM_PINS-1:0] TIMER_MASK  = 5'b11110,
    parameter [NUM_PINS-1:0] FIXED_MASK  = 0,
    parameter integer        PIN_ID_BASE = 5
) (
    input  wire                  clk,
    input  wire                  rst,
    // packet from bsd_parser
    input  wire                  pkt_valid_i,
    input  wire [1:0]            pkt_kind_i,
    input  wire [3:0]            pkt_n_i,
    input  wire [7:0]            pkt_d0_i,
    input  wire [7:0]            pkt_d1_i,
    input  wire [7:0]            pkt_d2_i,
    input  wire [39:0]           pkt_tail_i,    // d3..d7 (cmdDEBUG)
    // pin state
    input  wire [5*NUM_PINS-1:0] cfg_i,
    input  wire [NUM_PINS-1:0]   level_i,
    input  wire [NUM_PINS-1:0]   timer_busy_i,
    // configuration register file
    output wire                  cfg_we_o,
    output wire                  out_we_o,
    output wire [5:0]            pin_idx_o,     // the pin both writes address
    output wire [4:0]            cfg_wdata_o,
    output wire                  out_wdata_o,
    output wire [NUM_PINS-1:0]   rearm_o,
    // timers: start one, with the DEVCODE's delivery bits
    output wire [NUM_PINS-1:0]   timer_start_o,
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
    localparam [5:0] PIN_ID_W   = PIN_ID_BASE[5:0];

    // ------------------------------ stage 1: pin lookup and state-change decisions
    // A `pin` byte is the whole byte; a DEVCODE's pin is bits 5:0.
    wire [5:0] dev_pin = pkt_d1_i[5:0];

    // The addressed pin's state for stage 2's replies and messages.
    // Out-of-range pins read as zero; every use below is qualified by
    // pin_ok_q or dev_ok_q.
    reg [4:0]          look_cfg;
    reg                look_level;
    reg                look_fixed;
    reg                look_has_timer;
    integer i;
    always @* begin
        look_cfg        = 5'd0;
        look_level      = 1'b0;
        look_fixed      = 1'b0;
        look_has_timer  = 1'b0;
        for (i = 0; i < NUM_PINS; i = i + 1) begin
            if (dev_pin == i[5:0]) begin
                look_cfg        = cfg_i[5*i +: 5];
                look_level      = level_i[i];
                look_fixed      = FIXED_MASK[i];
                look_has_timer  = TIMER_MASK[i];
            end
        end
    end

    // The packet's kind, command and length as single flags, and the
    // decided state changes, worked out per pin (each pin's own bits and its
    // own address compare), so they do not wait for the lookup mux above.
    wire is_cmd = pkt_valid_i && pkt_kind_i == KIND_CMD;
    wire n_ge2  = pkt_n_i >= 4'd2;
    wire n_ge3  = pkt_n_i >= 4'd3;
    wire pin_ok = pkt_d1_i < NUM_PINS_W;
    wire dev_ok = {2'b00, dev_pin} < NUM_PINS_W;
    wire c_cfg  = is_cmd && pkt_d0_i == CMD_DIG_CFG && n_ge3;   // a DIG_CFG write
    wire c_out  = is_cmd && pkt_d0_i == CMD_DIG_IO && n_ge3;    // a DIG_IO write
    wire c_rst  = is_cmd && pkt_d0_i == CMD_DIG_RST && n_ge2;
    wire c_time = is_cmd && pkt_d0_i == CMD_PTIME_RD && n_ge2;

    // The addressed pin as a one-hot: two 3-bit decoders and one gate per pin
    // (a compare of the whole index per pin and strobe would cost several).
    // A `pin` byte must match whole (bits 7:6 zero); a DEVCODE's pin is its
    // bits 5:0.
    wire [7:0]          dec_lo = 8'd1 << dev_pin[2:0];
    wire [7:0]          dec_hi = 8'd1 << dev_pin[5:3];
    // Constant 0 (a lint sink for decoder lines that select no pin).
    /* verilator coverage_off */
    wire                unused_dec = ^{dec_lo, dec_hi};  // lines beyond NUM_PINS - 1
    /* verilator coverage_on */
    wire [NUM_PINS-1:0] sel;
    wire [NUM_PINS-1:0] is_input;
    genvar g;
    generate
        for (g = 0; g < NUM_PINS; g = g + 1) begin : g_sel
            assign sel[g]      = dec_hi[g / 8] && dec_lo[g % 8];
            assign is_input[g] = cfg_i[5*g + IODIR];
        end
    endgenerate
    wire                pin_byte = pkt_d1_i[7:6] == 2'b00;
    wire [NUM_PINS-1:0] do_cfg   = sel & {NUM_PINS{c_cfg && pin_byte}} & ~FIXED_MASK;
    wire [NUM_PINS-1:0] do_out   = sel & {NUM_PINS{c_out && pin_byte}} & ~is_input;
    wire [NUM_PINS-1:0] do_rst   = sel & {NUM_PINS{c_rst && pin_byte}};
    wire [NUM_PINS-1:0] do_start = sel & {NUM_PINS{c_time}} & TIMER_MASK & is_input & ~timer_busy_i;

    reg                s2_valid_q;
    reg                probe_q, serial_q, cmd_q;
    reg                is_hb_q, is_cfg_q, is_io_q, is_rst_q, is_debug_q, is_reset_q, is_invalid_q;
    reg [3:0]          n_q;
    reg                n1_q, n2_q, n_gt2_q, n_gt3_q;
    reg [7:0]          s2_d1_q, s2_d2_q;
    reg                pin_ok_q, dev_ok_q;
    reg [5:0]          dev_id_q;      // the DIG_IO pin's device ID
    reg [4:0]          pin_cfg_q;
    reg                pin_level_q, pin_fixed_q, pin_has_timer_q;
    reg                rst_ok_q;      // a DIG_RST re-arms
    reg                cfg_we_q, out_we_q, hb_answer_q;
    reg [NUM_PINS-1:0] rearm_q, start_q;

    always @(posedge clk) begin
        s2_valid_q      <= pkt_valid_i;
        probe_q         <= pkt_valid_i && pkt_kind_i == KIND_PROBE;
        serial_q        <= pkt_valid_i && pkt_kind_i == KIND_SERIAL;
        cmd_q           <= is_cmd;
        is_hb_q         <= pkt_d0_i == CMD_HB;
        is_cfg_q        <= pkt_d0_i == CMD_DIG_CFG;
        is_io_q         <= pkt_d0_i == CMD_DIG_IO;
        is_rst_q        <= pkt_d0_i == CMD_DIG_RST;
        is_debug_q      <= pkt_d0_i == CMD_DEBUG;
        is_reset_q      <= pkt_d0_i == CMD_RESET;
        is_invalid_q    <= !(pkt_d0_i == CMD_HB || pkt_d0_i == CMD_DIG_CFG || pkt_d0_i == CMD_DIG_IO ||
                             pkt_d0_i == CMD_DIG_RST || pkt_d0_i == CMD_PTIME_RD || pkt_d0_i == CMD_DEBUG ||
                             pkt_d0_i == CMD_RESET);
        n_q             <= pkt_n_i;
        n1_q            <= pkt_n_i == 4'd1;
        n2_q            <= pkt_n_i == 4'd2;
        n_gt2_q         <= pkt_n_i > 4'd2;
        n_gt3_q         <= pkt_n_i > 4'd3;
        s2_d1_q         <= pkt_d1_i;
        s2_d2_q         <= pkt_d2_i;
        pin_ok_q        <= pin_ok;
        dev_ok_q        <= dev_ok;
        dev_id_q        <= PIN_ID_W + dev_pin;
        pin_cfg_q       <= look_cfg;
        pin_level_q     <= look_level;
        pin_fixed_q     <= look_fixed;
        pin_has_timer_q <= look_has_timer;
        rst_ok_q        <= c_rst && pin_ok;
        cfg_we_q        <= |do_cfg;
        out_we_q        <= |do_out;
        hb_answer_q     <= is_cmd && pkt_d0_i == CMD_HB && n_ge2 &&
                           (pkt_d1_i == HB_UP + HB_ANSWER_OFFSET || pkt_d1_i == HB_DOWN + HB_ANSWER_OFFSET);
        rearm_q         <= do_cfg | do_rst;
        start_q         <= do_start;
        if (rst) begin
            s2_valid_q  <= 1'b0;
            probe_q     <= 1'b0;
            serial_q    <= 1'b0;
            cmd_q       <= 1'b0;
            rst_ok_q    <= 1'b0;
            cfg_we_q    <= 1'b0;
            out_we_q    <= 1'b0;
            hb_answer_q <= 1'b0;
            rearm_q     <= {NUM_PINS{1'b0}};
            start_q     <= {NUM_PINS{1'b0}};
        end
    end

    // ---------------------------------------------------- stage 2: execute
    wire       dev_host     = s2_d1_q[7];
    wire       dev_rflx     = s2_d1_q[6];
    wire       pin_is_input = pin_cfg_q[IODIR];

    assign cfg_we_o      = cfg_we_q;
    assign out_we_o      = out_we_q;
    assign rearm_o       = rearm_q;
    assign timer_start_o = start_q;
    assign hb_answer_o   = hb_answer_q;
    assign pin_idx_o     = s2_d1_q[5:0];
    assign cfg_wdata_o   = s2_d2_q[4:0];
    assign out_wdata_o   = s2_d2_q != 8'd0;
    assign timer_host_o  = dev_host;
    assign timer_rflx_o  = dev_rflx;
    assign hb_answer_down_o = s2_d1_q[0];  // type 3, as hb_answer_o comes only for 2 and 3
    // Any N: the power-up message that follows is the answer, so it is never cmdTooLong.
    assign soft_reset_o  = cmd_q && is_reset_q;

    // A DIG_IO read of an input pin with the RFLX bit: the same conditions as
    // its reply below, written flat since they enable the RFLX slot
    // (bsd_reply_slot).
    wire dio_rflx = cmd_q && is_io_q && n2_q && dev_ok_q && pin_is_input && dev_rflx;

    // The command changed state (each flag belongs to one command): check its length.
    wire acted = cfg_we_q || out_we_q || rst_ok_q || |start_q;

    // The reply or message of the packet in stage 2.
    reg        reply;
    reg [3:0]  reply_n;
    reg [31:0] reply_data;

    task message(input [7:0] code);
        begin
            reply      = 1'b1;
            reply_n    = 4'd2;
            reply_data = {CMD_MSG, code, 16'd0};
        end
    endtask

    always @* begin
        reply      = 1'b0;
        reply_n    = 4'd0;
        reply_data = 32'd0;

        if (probe_q) begin
            reply = 1'b1;  // A, 0
        end else if (serial_q) begin
            message(MSG_SERIAL_ERROR);
        end else if (cmd_q) begin
            if (is_hb_q) begin
                // Silent; stage 1 decided whether it answers.
            end else if (is_invalid_q) begin
                message(MSG_CMD_INVALID);
            end else if (is_reset_q) begin
                // No reply of its own: the reset puts the power-up message in the reply slot.
            end else if (is_debug_q) begin
                // The echo: the packet back as received, any N (bytes past N are not sent).
                reply      = 1'b1;
                reply_n    = n_q;
                reply_data = {CMD_DEBUG, s2_d1_q, s2_d2_q, pkt_tail_i[39:32]};
            end else if (n1_q) begin
                message(MSG_CMD_TOO_SHORT);
            end else if (acted) begin
                // Longest forms: DIG_CFG and DIG_IO take 3 bytes, DIG_RST and PTIME_RD 2.
                if ((is_cfg_q || is_io_q) ? n_gt3_q : n_gt2_q) message(MSG_CMD_TOO_LONG);
            end else if (is_cfg_q) begin
                // No write: a bad pin, a read, or a fixed pin.
                if (!pin_ok_q) message(MSG_CMD_INDEX_ERR);
                else if (n2_q) begin
                    reply      = 1'b1;
                    reply_n    = 4'd3;
                    reply_data = {CMD_DIG_CFG, s2_d1_q, pin_fixed_q, 2'b00, pin_cfg_q, 8'd0};
                end else message(MSG_CONFIG_ERR);
            end else if (is_io_q) begin
                // No write: a read, or a bad pin or an input pin for a write.
                if (!n2_q || !dev_ok_q || !pin_is_input) message(MSG_CMD_INDEX_ERR);
                else begin
                    if (dev_host) begin
                        reply      = 1'b1;
                        reply_n    = 4'd3;
                        reply_data = {CMD_DEV_VAL, 2'b00, dev_id_q, 7'd0, pin_level_q, 8'd0};
                    end
                end
            end else if (is_rst_q) begin
                message(MSG_CMD_INDEX_ERR);  // no re-arm: a bad pin
            end else begin
                // PTIME_RD without a start: a bad pin, or its timer is busy.
                if (!dev_ok_q || !pin_has_timer_q || !pin_is_input) message(MSG_CMD_INDEX_ERR);
                else message(MSG_TMR_CONFLICT);
            end
        end
    end

    assign s2_valid_o   = s2_valid_q;
    assign reply_o      = reply;
    assign reply_n_o    = reply_n;
    assign reply_data_o = reply_data;
    assign reply_tail_o = pkt_tail_i[31:0];
    assign dio_rflx_o   = dio_rflx;
    assign dio_id_o     = dev_id_q;
    assign dio_val_o    = pin_level_q;

`ifndef SYNTHESIS
`ifndef FORMAL  // Yosys takes no $fatal in an always block; the formal props assert it
    // Packets come at least three clocks apart (the two stages never overlap).
    reg chk_pkt1_q, chk_pkt2_q;
    always @(posedge clk) begin
        if (!rst && pkt_valid_i && (chk_pkt1_q || chk_pkt2_q))
            $fatal(1, "bsd_exec: a packet %0d clock(s) after the previous one (at least 3 apart)",
                   chk_pkt1_q ? 1 : 2);
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
