# SPDX-License-Identifier: Apache-2.0
"""A cocotb test module without a test: running it must fail (tb/runner/test_runner.py)."""
