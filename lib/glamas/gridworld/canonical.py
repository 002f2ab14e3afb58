"""A map file in its canonical form: ``python -m glamas.gridworld.canonical FILE`` prints it as
:func:`glamas.gridworld.maps.map_text` writes it (the form of the maps of ``data/maps``), and
``--write`` puts that form into the file. The reader takes any well-formed map
(:mod:`glamas.gridworld.maps`); the canonical form is one text per map, for files kept in the repository."""

import argparse

from glamas import errors
from glamas.gridworld.maps import canonical_difference, load_map, map_path, map_text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m glamas.gridworld.canonical", description=__doc__.split("\n\n")[0])
    parser.add_argument("map", help="a map file's path or the name of a map in data/maps")
    parser.add_argument("--write", action="store_true", help="replace the file's text by its canonical form")
    args = parser.parse_args(argv)
    path = map_path(args.map)
    text = map_text(load_map(path))
    if not args.write:
        print(text, end="")
    elif canonical_difference(path) is None:
        print(f"{path} is in its canonical form already")
    else:
        path.write_text(text)
        print(f"wrote {path} in its canonical form")
    return 0


if __name__ == "__main__":
    errors.run(main)
