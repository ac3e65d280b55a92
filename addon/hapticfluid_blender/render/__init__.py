# SPDX-License-Identifier: GPL-3.0-or-later
"""A baked cache on screen: the Volume object and its smoke material, the render scene, the farm's render task."""
