#!/usr/bin/env python3
"""Every number in the CSV files nhc simulate writes is the shortest text that reads back as the
same double (docs/scenes.md): runs of scenes with [outputs] columns, with contacts (extra columns)
and with --columns, each field compared with repr(float(field)), Python's shortest round-trip form.

    csv_numbers_test.py NHC SOURCE_DIR OUT_DIR
"""
import pathlib
import subprocess
import sys

RUNS = [
    ("examples/wheeled_pendulum.toml", []),           # [outputs] columns appended
    ("examples/car_parking.toml", []),
    ("examples/cylinder_incline.toml", []),          # contacts: extra columns
    ("examples/sliding_cylinder.toml", []),
    ("examples/chaplygin_sleigh.toml", []),          # the model's columns alone
    ("examples/wheeled_pendulum.toml", ["--columns", "t,x"]),
]


def longer_than_shortest(field):
    try:
        value = float(field)
    except ValueError:
        return False  # not a number (a header)
    shortest = repr(value)
    if shortest.endswith(".0"):
        shortest = shortest[:-2]
    return len(field) > len(shortest) and field.lower() not in ("nan", "inf", "-inf")


def main():
    nhc, source, out = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    out.mkdir(parents=True, exist_ok=True)
    problems, numbers = [], 0
    for k, (scene, flags) in enumerate(RUNS):
        csv = out / f"run{k}.csv"
        subprocess.run([nhc, "simulate", str(source / scene), "-o", str(csv), "--t-end", "0.5", *flags],
                       check=True, capture_output=True, text=True)
        lines = csv.read_text().splitlines()
        for row, line in enumerate(lines[1:], start=2):
            for column, field in enumerate(line.split(",")):
                numbers += 1
                if longer_than_shortest(field):
                    problems.append(f"{scene} {' '.join(flags)} line {row} column {lines[0].split(',')[column]}: "
                                    f"{field} (shortest {repr(float(field))})")
    for p in problems[:20]:
        print(p)
    print(f"{numbers} numbers read, {len(problems)} longer than their shortest form")
    return 1 if problems or numbers == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
