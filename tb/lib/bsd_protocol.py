# SPDX-License-Identifier: Apache-2.0
"""The protocol's constants for the testbenches: the host library's copy, which
tools/gen_protocol.py generates from tools/protocol.toml (one Python copy for both)."""

from brainstem_dio.protocol_table import *
