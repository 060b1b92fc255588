"""pcrt: ray tracing point clouds with the methods of the 2019 survey, from Python.

    import pcrt
    cloud = pcrt.load("sphere:n=100000")        # or a .ply/.xyz/.pwn/.off file
    scene = pcrt.Scene(cloud, method="goradia_2010", structure="octree", leaf_size=16)
    hits = scene.trace(origins, directions)     # numpy arrays: hit, t, position, normal, primitive
    image = scene.render(width=256, height=256) # (256, 256, 3) float32, linear
    runs = pcrt.read_sweep("results/thesis")    # pandas DataFrame (list of dicts without pandas)

Errors are pcrt.Error (a ValueError) with the one-line message the command line prints.
"""
import csv
import os

from ._pcrt import Cloud, Error, Scene, from_arrays, load, methods, read_exr, structures

__all__ = ["Cloud", "Error", "Scene", "from_arrays", "load", "methods", "read_exr", "structures",
           "read_sweep"]


def read_sweep(directory):
    """The runs of a sweep directory (its runs.csv, one row per run).

    A pandas DataFrame when pandas is installed, else a list of dicts of strings.
    """
    path = os.path.join(directory, "runs.csv")
    if not os.path.isfile(path):
        raise Error(f"{path}: no such file (is {directory} a sweep directory?)")
    try:
        import pandas
    except ImportError:
        pandas = None
    # A damaged runs.csv (torn, emptied, not text) is pcrt.Error naming it, as in the command line.
    try:
        if pandas is None:
            with open(path, newline="", encoding="utf-8") as f:
                rows = list(csv.reader(f, strict=True))
            if not rows:
                raise Error(f"{path}: empty: not a runs.csv pcrt wrote")
            for i, row in enumerate(rows[1:], start=1):
                if len(row) != len(rows[0]):
                    raise Error(f"{path}: run {i} has {len(row)} fields where the header has "
                                f"{len(rows[0])}: not a runs.csv pcrt wrote")
            return [dict(zip(rows[0], row)) for row in rows[1:]]
        return pandas.read_csv(path, encoding="utf-8")
    except UnicodeDecodeError as e:
        raise Error(f"{path}: not UTF-8 text: not a runs.csv pcrt wrote") from None
    except csv.Error as e:
        raise Error(f"{path}: {e}: not a runs.csv pcrt wrote") from None
    except Exception as e:
        if pandas is not None and isinstance(e, (pandas.errors.ParserError,
                                                 pandas.errors.EmptyDataError)):
            first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise Error(f"{path}: {first}: not a runs.csv pcrt wrote") from None
        raise
