"""The command reference (``docs/cli.md``), generated from the parser so it cannot drift from it.

``python -m instrument.cli_reference > docs/cli.md`` rewrites it; a test compares the two.
"""

from __future__ import annotations

import argparse
import os

from .cli import build_parser

#: the help text's width (columns), fixed so the page does not depend on the terminal it was made in
WIDTH = 100


def cli_reference() -> str:
    """Markdown: each command's ``--help``, in the parser's order."""
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(WIDTH)
    try:
        parser = build_parser()
        parts = ["# Command reference", "",
                 "Generated from the parser (`python -m instrument.cli_reference > docs/cli.md`); every command also "
                 "answers `--help`.", "", "```text", parser.format_help().rstrip(), "```", ""]
        for action in parser._subparsers._group_actions if parser._subparsers else []:
            if not isinstance(action, argparse._SubParsersAction):
                continue
            for name, sub in action.choices.items():
                parts += [f"## instrument {name}", "", "```text", sub.format_help().rstrip(), "```", ""]
                nested = [a for a in sub._actions if isinstance(a, argparse._SubParsersAction)]
                for group in nested:
                    for inner, inner_parser in group.choices.items():
                        parts += [f"### instrument {name} {inner}", "", "```text", inner_parser.format_help().rstrip(),
                                  "```", ""]
        return "\n".join(parts)
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old


if __name__ == "__main__":
    print(cli_reference(), end="")
