# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake's interface: Physics and Scene panels, the Timeline's cache bar, preferences, wrapped text."""
