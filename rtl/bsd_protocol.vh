// Protocol constants of the BrainStem 1.0 packet link (PROTOCOL.md §2, §3),
// included inside the modules that need them. Each module uses only some of
// them, so unused ones are not worth a warning there.
/* verilator lint_off UNUSEDPARAM */
localparam [7:0] CMD_HB       = 8'd0;
localparam [7:0] CMD_DEV_VAL  = 8'd4;
localparam [7:0] CMD_DIG_CFG  = 8'd26;
localparam [7:0] CMD_DIG_IO   = 8'd27;
localparam [7:0] CMD_DIG_RST  = 8'd28;
localparam [7:0] CMD_PTIME_RD = 8'd29;
localparam [7:0] CMD_MSG      = 8'h80;

localparam [7:0] MSG_STATE_POWER_RESET = 8'd4;
localparam [7:0] MSG_CMD_INVALID       = 8'd8;
localparam [7:0] MSG_CMD_TOO_LONG      = 8'd9;
localparam [7:0] MSG_CMD_INDEX_ERR     = 8'd10;
localparam [7:0] MSG_TMR_CONFLICT      = 8'd15;
localparam [7:0] MSG_CMD_TOO_SHORT     = 8'd27;
localparam [7:0] MSG_SERIAL_ERROR      = 8'd28;
localparam [7:0] MSG_CONFIG_ERR        = 8'd29;

localparam [7:0] ADDR_RESYNC = 8'hAD;
localparam [7:0] MAX_N       = 8'd8;

// cmdHB type bytes: the core's UP/DOWN heartbeats; the host answers with +2.
localparam [7:0] HB_UP   = 8'd0;
localparam [7:0] HB_DOWN = 8'd1;
localparam [7:0] HB_ANSWER_OFFSET = 8'd2;

// Heartbeat period unit and the timer tick, in ticks of 1.6 us and in Hz.
localparam integer TICK_HZ       = 625_000;
localparam integer HB_UNIT_TICKS = 16_000;  // 25.6 ms

// Packet kinds from the parser to the executor.
localparam [1:0] KIND_CMD    = 2'd0;
localparam [1:0] KIND_PROBE  = 2'd1;
localparam [1:0] KIND_SERIAL = 2'd2;
/* verilator lint_on UNUSEDPARAM */
