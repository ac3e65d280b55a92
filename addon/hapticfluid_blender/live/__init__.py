# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session: its settings, operators, controller, panel and viewport drawing."""
