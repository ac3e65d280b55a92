# SPDX-License-Identifier: GPL-3.0-or-later
"""Text for panels: long messages wrapped to the region's width (Blender's labels do not wrap).
Imports nothing of the add-on, so any panel or preference may use it."""

import textwrap

CHAR_WIDTH_PX = 7  # about one character of the UI font at scale 1, for wrapping long text


def wrapped_label(layout, context, text, icon="NONE"):
    """``text`` as several labels that fit the region's width (Blender's labels do not wrap)."""
    region = getattr(context, "region", None)
    width_px = region.width if region is not None and region.width > 1 else 400
    scale = context.preferences.system.ui_scale if context.preferences else 1.0
    scale = scale if scale > 0.0 else 1.0  # 0 in background mode
    chars = max(24, int(width_px / (CHAR_WIDTH_PX * scale)) - 6)
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, chars) or [""]):
        col.label(text=line, icon=icon if i == 0 else ("BLANK1" if icon != "NONE" else "NONE"))
    return col
