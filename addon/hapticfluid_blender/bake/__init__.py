# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene as a bake: its export (with the smoke source's mesh), the re-bake plan and the command-line bake."""
