`default_nettype none
// Executes one packet from the parser in two clocks: the first looks up the
// addressed pin's state (a wide mux on many-pin builds) into registers; the
// second decides the outcome with the contract's precedence (cmdInvalid,
// cmdTooShort, the command's own error, then the action and cmdTooLong) and
// drives the state changes as one-clock strobes. Packets come at least three
// clocks apart, so the stages never overlap. Holds the one waiting reply (a
// packet of up to 4 data bytes) and the one waiting DIG_IO RFLX value.
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
    // pin state
    input  wire [5*NUM_PINS-1:0] cfg_i,
    input  wire [NUM_PINS-1:0]   level_i,
    input  wire [NUM_PINS-1:0]   timer_busy_i,
    output wire                  busy_o,      // a packet is being executed
    // configuration register file
    output reg                   cfg_we_o,
    output reg                   out_we_o,
    output wire [5:0]            pin_o,
    output wire [4:0]            cfg_o,
    output wire                  out_o,
    output reg  [NUM_PINS-1:0]   rearm_o,
    // timers: start one, with the DEVCODE's delivery bits
    output reg  [NUM_PINS-1:0]   timer_start_o,
    output wire                  timer_host_o,
    output wire                  timer_rflx_o,
    // heartbeat answer from the host
    output reg                   hb_answer_o,
    output wire [7:0]            hb_type_o,
    // the waiting reply: A, rep_n, rep_data[31:24] ...
    output reg                   rep_req_o,
    output reg  [2:0]            rep_n_o,
    output reg  [31:0]           rep_data_o,
    input  wire                  rep_done_i,
    // the waiting DIG_IO RFLX value
    output reg                   dio_rflx_req_o,
    output reg  [5:0]            dio_rflx_id_o,
    output reg                   dio_rflx_val_o,
    input  wire                  dio_rflx_done_i
);
    `include "bsd_protocol.vh"

    localparam integer IODIR = 0;  // DIGCFG bit: 1 = input
    localparam [7:0] NUM_PINS_W = NUM_PINS[7:0];
    localparam [5:0] PIN_ID_W   = PIN_ID_BASE[5:0];

    // ------------------------------------------------ stage 1: pin lookup
    // A `pin` byte is the whole byte; a DEVCODE's pin is bits 5:0.
    wire [5:0] pin_in = pkt_d1_i[5:0];

    // The addressed pin's state. Out-of-range pins read as zero; every use
    // below is qualified by pin_ok_q or dev_ok_q.
    reg [4:0]          look_cfg;
    reg                look_level;
    reg                look_fixed;
    reg                look_has_timer;
    reg                look_timer_busy;
    reg [NUM_PINS-1:0] look_onehot;
    integer i;
    always @* begin
        look_cfg        = 5'd0;
        look_level      = 1'b0;
        look_fixed      = 1'b0;
        look_has_timer  = 1'b0;
        look_timer_busy = 1'b0;
        look_onehot     = {NUM_PINS{1'b0}};
        for (i = 0; i < NUM_PINS; i = i + 1) begin
            if (pin_in == i[5:0]) begin
                look_cfg        = cfg_i[5*i +: 5];
                look_level      = level_i[i];
                look_fixed      = FIXED_MASK[i];
                look_has_timer  = TIMER_MASK[i];
                look_timer_busy = timer_busy_i[i];
                look_onehot[i]  = 1'b1;
            end
        end
    end

    reg                s_valid_q;
    reg [1:0]          s_kind_q;
    reg [3:0]          s_n_q;
    reg [7:0]          s_d0_q, s_d1_q, s_d2_q;
    reg                pin_ok_q, dev_ok_q;
    reg [4:0]          pin_cfg_q;
    reg                pin_level_q, pin_fixed_q, pin_has_timer_q, pin_timer_busy_q;
    reg [NUM_PINS-1:0] pin_onehot_q;

    always @(posedge clk) begin
        s_valid_q        <= pkt_valid_i;
        s_kind_q         <= pkt_kind_i;
        s_n_q            <= pkt_n_i;
        s_d0_q           <= pkt_d0_i;
        s_d1_q           <= pkt_d1_i;
        s_d2_q           <= pkt_d2_i;
        pin_ok_q         <= pkt_d1_i < NUM_PINS_W;
        dev_ok_q         <= {2'b00, pin_in} < NUM_PINS_W;
        pin_cfg_q        <= look_cfg;
        pin_level_q      <= look_level;
        pin_fixed_q      <= look_fixed;
        pin_has_timer_q  <= look_has_timer;
        pin_timer_busy_q <= look_timer_busy;
        pin_onehot_q     <= look_onehot;
        if (rst) s_valid_q <= 1'b0;
    end

    assign busy_o = pkt_valid_i || s_valid_q;

    // ---------------------------------------------------- stage 2: execute
    wire       is_cmd       = s_kind_q == KIND_CMD;
    wire [7:0] cmd          = s_d0_q;
    wire       dev_host     = s_d1_q[7];
    wire       dev_rflx     = s_d1_q[6];
    wire [5:0] pin          = s_d1_q[5:0];
    wire       pin_is_input = pin_cfg_q[IODIR];

    assign pin_o        = pin;
    assign cfg_o        = s_d2_q[4:0];
    assign out_o        = s_d2_q != 8'd0;
    assign timer_host_o = dev_host;
    assign timer_rflx_o = dev_rflx;
    assign hb_type_o    = s_d1_q;

    // Outcome of the packet in stage 2.
    reg        reply;       // a reply or message goes to the slot
    reg [2:0]  reply_n;
    reg [31:0] reply_data;
    reg        dio_rflx;
    reg        ok;          // the command succeeded: check its length

    task message(input [7:0] code);
        begin
            reply      = 1'b1;
            reply_n    = 3'd2;
            reply_data = {CMD_MSG, code, 16'd0};
        end
    endtask

    always @* begin
        cfg_we_o      = 1'b0;
        out_we_o      = 1'b0;
        rearm_o       = {NUM_PINS{1'b0}};
        timer_start_o = {NUM_PINS{1'b0}};
        hb_answer_o   = 1'b0;
        reply         = 1'b0;
        reply_n       = 3'd0;
        reply_data    = 32'd0;
        dio_rflx      = 1'b0;
        ok            = 1'b0;

        if (s_valid_q && s_kind_q == KIND_PROBE) begin
            reply = 1'b1;  // A, 0
        end else if (s_valid_q && s_kind_q == KIND_SERIAL) begin
            message(MSG_SERIAL_ERROR);
        end else if (s_valid_q && is_cmd) begin
            case (cmd)
                CMD_HB: begin
                    // Always silent; a 2-byte or longer packet may answer.
                    hb_answer_o = s_n_q >= 4'd2;
                end
                CMD_DIG_CFG: begin
                    if (s_n_q == 4'd1) message(MSG_CMD_TOO_SHORT);
                    else if (!pin_ok_q) message(MSG_CMD_INDEX_ERR);
                    else if (s_n_q == 4'd2) begin
                        reply      = 1'b1;
                        reply_n    = 3'd3;
                        reply_data = {CMD_DIG_CFG, s_d1_q, pin_fixed_q, 2'b00, pin_cfg_q, 8'd0};
                    end else if (pin_fixed_q) message(MSG_CONFIG_ERR);
                    else begin
                        cfg_we_o      = 1'b1;
                        rearm_o       = pin_onehot_q;
                        ok            = 1'b1;
                    end
                end
                CMD_DIG_IO: begin
                    if (s_n_q == 4'd1) message(MSG_CMD_TOO_SHORT);
                    else if (s_n_q == 4'd2) begin
                        if (!dev_ok_q || !pin_is_input) message(MSG_CMD_INDEX_ERR);
                        else begin
                            if (dev_host) begin
                                reply      = 1'b1;
                                reply_n    = 3'd3;
                                reply_data = {CMD_DEV_VAL, 2'b00, PIN_ID_W + pin, 7'd0, pin_level_q, 8'd0};
                            end
                            dio_rflx = dev_rflx;
                        end
                    end else if (!pin_ok_q || pin_is_input) message(MSG_CMD_INDEX_ERR);
                    else begin
                        out_we_o = 1'b1;
                        ok       = 1'b1;
                    end
                end
                CMD_DIG_RST: begin
                    if (s_n_q == 4'd1) message(MSG_CMD_TOO_SHORT);
                    else if (!pin_ok_q) message(MSG_CMD_INDEX_ERR);
                    else begin
                        rearm_o      = pin_onehot_q;
                        ok           = 1'b1;
                    end
                end
                CMD_PTIME_RD: begin
                    if (s_n_q == 4'd1) message(MSG_CMD_TOO_SHORT);
                    else if (!dev_ok_q || !pin_has_timer_q || !pin_is_input) message(MSG_CMD_INDEX_ERR);
                    else if (pin_timer_busy_q) message(MSG_TMR_CONFLICT);
                    else begin
                        timer_start_o      = pin_onehot_q;
                        ok                 = 1'b1;
                    end
                end
                default: message(MSG_CMD_INVALID);
            endcase
            // Longest forms: DIG_CFG and DIG_IO take 3 bytes, DIG_RST and PTIME_RD 2.
            if (ok && s_n_q > ((cmd == CMD_DIG_CFG || cmd == CMD_DIG_IO) ? 4'd3 : 4'd2))
                message(MSG_CMD_TOO_LONG);
        end
    end

    // Registers: the waiting reply and the waiting DIG_IO RFLX value. The
    // parser never completes a packet that could need a slot while it is full.
    always @(posedge clk) begin
        if (rep_done_i) rep_req_o <= 1'b0;
        if (reply) begin
            rep_req_o  <= 1'b1;
            rep_n_o    <= reply_n;
            rep_data_o <= reply_data;
        end
        if (dio_rflx_done_i) dio_rflx_req_o <= 1'b0;
        if (dio_rflx) begin
            dio_rflx_req_o <= 1'b1;
            dio_rflx_id_o  <= PIN_ID_W + pin;
            dio_rflx_val_o <= pin_level_q;
        end
        if (rst) begin
            // The power-up message is the first packet out.
            rep_req_o      <= 1'b1;
            rep_n_o        <= 3'd2;
            rep_data_o     <= {CMD_MSG, MSG_STATE_POWER_RESET, 16'd0};
            dio_rflx_req_o <= 1'b0;
            dio_rflx_id_o  <= 6'd0;
            dio_rflx_val_o <= 1'b0;
        end
    end
endmodule
`default_nettype wire
