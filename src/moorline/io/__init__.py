"""MoorDyn v2 input decks: :func:`read_deck`, :func:`write_deck` and EA/BA/EI curve files."""

from .deck import read_curve, read_deck, read_deck_text, write_deck

__all__ = ["read_curve", "read_deck", "read_deck_text", "write_deck"]
