"""Figures of members, chains and fits (matplotlib, written atomically)."""
