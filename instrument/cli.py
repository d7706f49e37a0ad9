"""The ``instrument`` command line."""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="instrument", description="AFO stiffness and passive muscle-tendon lab instrument")
    parser.add_argument("-v", "--verbose", action="store_true", help="log driver events")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="run the simulated lab through the real drivers (no hardware)")
    demo.add_argument("--seconds", type=float, default=4.0, help="streaming time per run (s)")
    demo.add_argument("--out", type=Path, default=Path("out"), help="output folder")
    demo.add_argument("--no-faults", action="store_true", help="skip the fault drill")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING)
    if args.command == "demo":
        from .demo import main as demo_main

        return demo_main(args.seconds, args.out, faults=not args.no_faults)
    return 2


if __name__ == "__main__":
    sys.exit(main())
