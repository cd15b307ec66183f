#!/usr/bin/python3
"""Check that a `spall run` output folder is whole, as a run killed at any moment must leave it:
the .pvd series parses and every file it lists opens in VTK's own reader with the same number of
points; every .csv history has a header and only complete rows (as many cells as the header, each
a number, the last line ended); run.json, when present, parses. Prints one line per problem and
exits 1 if there is any, else prints "whole: ..." and exits 0.
Run it with Debian's interpreter, which has python3-vtk9: /usr/bin/python3 tools/check_output.py DIR
"""
import argparse
import json
import pathlib
import sys
import xml.etree.ElementTree as ElementTree

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import read_vtu  # noqa: E402  (VTK's reader with its errors caught)


def check_series(folder, problems):
    pvd = folder / "d3plot.pvd"
    if not pvd.exists():
        return 0
    try:
        datasets = ElementTree.parse(pvd).getroot().findall("./Collection/DataSet")
    except ElementTree.ParseError as error:
        problems.append(f"{pvd}: not valid XML ({error})")
        return 0
    points = set()
    for dataset in datasets:
        path = folder / dataset.get("file")
        if not path.exists():
            problems.append(f"{pvd} lists {path.name}, which is missing")
            continue
        try:
            points.add(read_vtu.read(str(path)).GetNumberOfPoints())
        except SystemExit as error:
            problems.append(str(error))
    if len(points) > 1:
        problems.append(f"{pvd}: its files have different point counts {sorted(points)}")
    return len(datasets)


def check_history(path, problems):
    text = path.read_text()
    if not text.endswith("\n"):
        problems.append(f"{path}: the last line is cut")
    lines = text.splitlines()
    if not lines:
        problems.append(f"{path}: empty, not even a header")
        return 0
    columns = len(lines[0].split(","))
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != columns:
            problems.append(f"{path}:{number}: {len(cells)} cells, the header has {columns}")
            continue
        try:
            [float(cell) for cell in cells]
        except ValueError:
            problems.append(f"{path}:{number}: not all numbers")
    return len(lines) - 1


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=pathlib.Path)
    folder = parser.parse_args().folder
    problems = []
    states = check_series(folder, problems)
    rows = sum(check_history(path, problems) for path in sorted(folder.glob("*.csv")))
    if (folder / "run.json").exists():
        try:
            json.loads((folder / "run.json").read_text())
        except ValueError as error:
            problems.append(f"{folder / 'run.json'}: not valid JSON ({error})")
    for problem in problems:
        print(problem)
    if problems:
        sys.exit(1)
    print(f"whole: {states} states in d3plot.pvd, {rows} history rows")


if __name__ == "__main__":
    main()
