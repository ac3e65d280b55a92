# SPDX-License-Identifier: GPL-3.0-or-later
"""What a .blend stores: the objects' roles and their settings, read through roles; older files' layout."""
