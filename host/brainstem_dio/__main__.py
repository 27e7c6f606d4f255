# SPDX-License-Identifier: Apache-2.0
"""`python -m brainstem_dio` = the `brainstem-dio` command."""

import sys

from .cli import main

sys.exit(main())
