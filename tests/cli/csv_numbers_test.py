#!/usr/bin/env python3
"""Every number in the data files nhc writes is the shortest text that reads back as the same double
(docs/scenes.md): each field compared with repr(float(field)), Python's shortest round-trip form.

The files: nhc simulate's CSV (scenes with [outputs] columns, with contacts' extra columns, with
--columns, with --sensitivity) and its event table; nhc optimize -o; nhc connect -o; nhc compare's
CSV files; nhc report's workprec.csv and plot data; nhc linearize -o's CSV and JSON; the JSON of
derive and analyze --format json; analyze --write-initial.

    csv_numbers_test.py NHC SOURCE_DIR OUT_DIR
"""
import json
import pathlib
import re
import shutil
import subprocess
import sys

SIMULATE = [
    ("examples/wheeled_pendulum.toml", []),           # [outputs] columns appended
    ("examples/car_parking.toml", []),
    ("examples/cylinder_incline.toml", []),          # contacts: extra columns
    ("examples/sliding_cylinder.toml", []),
    ("examples/chaplygin_sleigh.toml", []),          # the model's columns alone
    ("examples/wheeled_pendulum.toml", ["--columns", "t,x"]),
    ("examples/wheeled_pendulum.toml", ["--sensitivity", "mb"]),    # the sensitivities' columns
    ("examples/chaplygin_sleigh.toml", ["--stop-when", "t - 0.1"]),  # the event table beside the CSV
]


def longer_than_shortest(field):
    try:
        value = float(field)
    except ValueError:
        return False  # not a number (a header, a name)
    shortest = repr(value)
    if shortest.endswith(".0"):
        shortest = shortest[:-2]
    return len(field) > len(shortest) and field.lower() not in ("nan", "inf", "-inf")


class Checker:
    def __init__(self):
        self.problems, self.numbers, self.files = [], 0, 0

    def field(self, where, field):
        self.numbers += 1
        if longer_than_shortest(field):
            self.problems.append(f"{where}: {field} (shortest {repr(float(field))})")

    def csv(self, path, separator=","):
        """A CSV (or whitespace-separated gnuplot data) file: every field of every row after the header."""
        self.files += 1
        lines = path.read_text().splitlines()
        header = lines[0].split(separator) if separator == "," else []
        for row, line in enumerate(lines[1 if separator == "," else 0:], start=2 if separator == "," else 1):
            if not line.strip() or line.startswith("#"):
                continue
            fields = line.split(separator) if separator == "," else line.split()
            for column, field in enumerate(fields):
                name = header[column] if column < len(header) else str(column + 1)
                self.field(f"{path.name} line {row} column {name}", field)

    def json_text(self, name, text):
        """Each number token of a JSON text, as written (json's parse hooks see the token's text)."""
        self.files += 1
        hook = lambda token: self.field(f"{name} (JSON)", token)  # noqa: E731
        json.loads(text, parse_float=hook, parse_int=hook)

    def toml_initial(self, path):
        """The values of an [initial] table nhc wrote (name = [v, v'] lines and t0 = v)."""
        self.files += 1
        for row, line in enumerate(path.read_text().splitlines(), start=1):
            match = re.fullmatch(r"\s*[A-Za-z_][\w']*\s*=\s*\[?([^\]\"]*)\]?\s*", line)
            if match:
                for field in match.group(1).split(","):
                    field = field.strip()
                    if field.endswith(".0"):  # TOML's mark of a float, not a digit
                        field = field[:-2]
                    if field:
                        self.field(f"{path.name} line {row}", field)


def run(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)} exited {result.returncode}:\n{result.stdout}{result.stderr}")
    return result.stdout


def main():
    nhc, source, out = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    if out.exists():
        shutil.rmtree(out)  # no file of an earlier run is read as this one's
    out.mkdir(parents=True)
    check = Checker()
    for k, (scene, flags) in enumerate(SIMULATE):
        csv = out / f"run{k}.csv"
        run([nhc, "simulate", str(source / scene), "-o", str(csv), "--t-end", "0.5", *flags])
        check.csv(csv)
        if (out / f"run{k}.events.csv").exists():
            check.csv(out / f"run{k}.events.csv")
    if not (out / f"run{len(SIMULATE) - 1}.events.csv").exists():
        sys.exit("--stop-when wrote no event table")

    optimal = out / "optimal.csv"
    run([nhc, "optimize", str(source / "examples/heisenberg_optimal.toml"), "--intervals", "10", "-o", str(optimal)])
    check.csv(optimal)

    connected = out / "connect.csv"
    run([nhc, "connect", str(source / "examples/heisenberg.toml"), "--to", "x=1,y=0,z=0.25", "--t-end", "1", "-o",
         str(connected)])
    check.csv(connected)

    compared = out / "compare"
    run([nhc, "compare", str(source / "examples/chaplygin_sleigh.toml"), "--t-end", "0.5", "-o", str(compared)])
    for data in sorted(compared.glob("*.csv")):
        check.csv(data)

    report = out / "report"
    run([nhc, "report", str(source / "examples/chaplygin_sleigh.toml"), "--tolerances", "1e-3:1e-4", "--repeats", "1",
         "--jacobian", "dense", "--projection", "off", "--t-end", "0.5", "--quiet", "-o", str(report)])
    check.csv(report / "workprec.csv")
    for data in sorted(report.glob("*.dat")):
        check.csv(data, separator=None)

    lin = out / "lin"
    run([nhc, "linearize", str(source / "tests/linearize/scenes/rolling_disk.toml"), "--sweep", "ps'=0.5:6:4", "-o",
         str(lin)])
    for data in sorted(lin.glob("*.csv")):
        check.csv(data)
    check.json_text("linearize.json", (lin / "linearize.json").read_text())

    for scene in ("examples/wheeled_pendulum.toml", "examples/rolling_disk.toml"):
        check.json_text(f"derive {scene}", run([nhc, "derive", str(source / scene), "--format", "json"]))
        check.json_text(f"analyze {scene}", run([nhc, "analyze", str(source / scene), "--format", "json"]))

    initial = out / "initial.toml"
    run([nhc, "analyze", str(source / "examples/rolling_disk.toml"), "--repair-initial", "--write-initial",
         str(initial)])
    check.toml_initial(initial)

    for p in check.problems[:20]:
        print(p)
    print(f"{check.numbers} numbers read in {check.files} files, {len(check.problems)} longer than their shortest form")
    return 1 if check.problems or check.numbers == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
