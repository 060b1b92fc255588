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
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    return pandas.read_csv(path)
