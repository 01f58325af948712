"""Every flag of the command line is named on the command reference (docs/commands.md).

Reads `nhc --help` for the commands and `nhc <command> --help` for each one's flags (the command
line's own text, which the docs build also prints whole as commands-help.md) and fails (exit 1)
naming each long flag, with its command, that docs/commands.md does not mention.
usage: command_flags.py --nhc NHC [--page docs/commands.md]
"""
import argparse
import pathlib
import re
import subprocess
import sys


def helptext(nhc, *args):
    return subprocess.run([nhc, *args, "--help"], capture_output=True, text=True, timeout=60, check=True).stdout


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nhc", required=True)
    parser.add_argument("--page", type=pathlib.Path, default=pathlib.Path(__file__).parent / "commands.md")
    args = parser.parse_args()
    page = args.page.read_text(encoding="utf-8")
    listing = helptext(args.nhc).split("Subcommands:", 1)[1]
    commands = re.findall(r"^  ([a-z]+) ", listing, re.M)
    if len(commands) < 5:
        sys.exit(f"command_flags.py: nhc --help listed only {commands}")
    missing, count = [], 0
    for command in commands:
        if not re.search(rf"^## {command}\b|`nhc {command}\b", page, re.M):
            missing.append(f"nhc {command} (neither a section '## {command}' nor `nhc {command}`)")
        for flag in sorted(set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", helptext(args.nhc, command)))):
            if flag == "--help":
                continue
            count += 1
            if not re.search(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", page):
                missing.append(f"nhc {command} {flag}")
    if missing:
        sys.exit(f"command_flags.py: {args.page.name} does not mention:\n  " + "\n  ".join(missing))
    print(f"command flags: {count} flags of {len(commands)} commands, all on {args.page.name}")


if __name__ == "__main__":
    main()
