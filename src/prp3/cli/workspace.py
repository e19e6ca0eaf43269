"""``prp3 workspace``: not implemented yet."""

from __future__ import annotations

import argparse
from typing import Any


def register(subparsers: Any) -> None:
    """Add the ``workspace`` subcommand (placeholder)."""
    parser = subparsers.add_parser("workspace", help="(not implemented yet)")
    parser.set_defaults(handler=None)


def handler(args: argparse.Namespace) -> int:  # pragma: no cover - placeholder
    raise NotImplementedError
