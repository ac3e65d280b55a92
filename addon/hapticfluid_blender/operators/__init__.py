# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake's and the farm job's operators, and the guard every modal operator starts through."""
