"""Memory bounded everywhere: every command estimates what its input
will allocate and refuses it, before allocating, with one line and exit status 2 when
that exceeds the memory available or PARCOVER_MEMORY_LIMIT.

Refusals are run under a small cap (never gigabytes); the command-line ones in a
subprocess, whose peak RSS and time are measured.
"""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from parcover import generate, memory, write_instance
from parcover.cli import main
from parcover.errors import InputError
from parcover.maps import read_free_mask

CAP = "50MB"
#: A refused command loads the interpreter, numpy and parcover, nothing more (about 80 MB).
SMALL_RSS_KB = 250_000


def _png_header(path: Path, width: int, height: int) -> None:
    """A PNG file of a few hundred bytes whose header claims ``width x height`` grey pixels
    (its data holds one row: decoding it would fail, reading its header does not)."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    row = zlib.compress(bytes(width + 1))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", row) + chunk(b"IEND", b""))


#: Runs parcover in a child and prints its exit status, peak RSS (KB) and stderr. A child
#: of the test process would start its peak RSS at the test's own (Linux carries it over
#: fork and exec); a child of this small program starts at this program's.
_MEASURE = """
import json, resource, subprocess, sys
done = subprocess.run([sys.executable, "-m", "parcover", *sys.argv[1:]], capture_output=True, text=True)
print(json.dumps([done.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, done.stdout, done.stderr]))
"""


def _refused_in_subprocess(argv: list[str], message: str) -> None:
    """``parcover argv`` under :data:`CAP`: exit 2 with one line holding ``message``, within
    5 s, its peak RSS small."""
    env = {**os.environ, memory.LIMIT_VARIABLE: CAP}
    started = time.monotonic()
    measured = subprocess.run([sys.executable, "-c", _MEASURE, *argv], env=env, capture_output=True, text=True,
                              check=True, timeout=60)
    seconds = time.monotonic() - started
    code, peak_kb, out, err = json.loads(measured.stdout)
    assert code == 2, err
    assert out == "" and message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert seconds < 5, seconds
    assert peak_kb < SMALL_RSS_KB, peak_kb  # kilobytes on Linux


def _refused(capsys, monkeypatch, argv: list[str], message: str) -> None:
    monkeypatch.setenv(memory.LIMIT_VARIABLE, CAP)
    try:
        code = main(argv)
    except SystemExit as exc:
        code = int(exc.code or 0)
    _, err = capsys.readouterr()
    assert code == 2, err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


# -- the estimator and the cap ----------------------------------------------------


@pytest.mark.parametrize(
    ("text", "size"),
    [("123", 123), ("2GB", 2 * 10**9), ("2 gb", 2 * 10**9), ("1.5M", 1_500_000), ("512MiB", 512 * 2**20),
     ("1e9", 10**9), ("3KiB", 3072)],
)
def test_the_cap_reads_bytes_and_units(text, size):
    assert memory.parse_size(text) == size


@pytest.mark.parametrize("text", ["abc", "0", "-1GB", "2 XB", "GB"])
def test_a_bad_cap_is_one_line(capsys, monkeypatch, text):
    monkeypatch.setenv(memory.LIMIT_VARIABLE, text)
    assert main(["generate", "star", "--n", "3"]) == 2
    err = capsys.readouterr().err
    assert "PARCOVER_MEMORY_LIMIT=" in err and "is not a size" in err and len(err.splitlines()) == 1


def test_the_cap_is_the_smaller_of_itself_and_the_memory_available(monkeypatch):
    monkeypatch.setenv(memory.LIMIT_VARIABLE, "1TB" if memory.available_memory() else "1KB")
    limit, source = memory.memory_limit()
    available = memory.available_memory()
    assert (limit, source) == ((available, "available") if available else (1000, "allowed by PARCOVER_MEMORY_LIMIT"))
    monkeypatch.setenv(memory.LIMIT_VARIABLE, "1KB")
    assert memory.memory_limit() == (1000, "allowed by PARCOVER_MEMORY_LIMIT")


def test_the_estimate_covers_what_an_instance_takes():
    # tracemalloc's peak of building random points, a graph of many virtual nodes, a grid
    import tracemalloc

    generate.random_graph(3, 0)  # scipy's modules loaded: their import is not the instance's
    for kind, sizes in (("random", {"n": 300}), ("graph", {"n": 20, "virtual": 3000}), ("graph", {"n": 300}),
                        ("grid", {"rows": 30, "cols": 30})):
        build = {"random": generate.random_points, "graph": generate.random_graph, "grid": generate.grid}[kind]
        tracemalloc.start()
        instance = build(**sizes)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        estimate = generate.footprint(kind, **sizes)  # a graph's edges counted high: 3 per node
        assert memory.footprint_of(instance).peak <= estimate.peak
        assert peak <= estimate.peak <= 4 * peak


# -- generators, files, maps, reports: refused before allocating --------------------


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["generate", "random", "--n", "1000000000"], "A random instance of 1000000000 KPOIs needs about 2.4e+07 TB"),
        (["generate", "star", "--n", "100000"], "A star of 100000 KPOIs needs about 240.1 GB"),
        (["generate", "grid", "--rows", "100000", "--cols", "100000"], "A 100000 x 100000 grid needs about"),
        (["generate", "graph", "--n", "10", "--virtual", "1000000000"], "A graph of 10 KPOIs and 1000000000 virtual"),
    ],
)
def test_a_generator_too_large_is_refused_quickly(argv, message):
    _refused_in_subprocess(argv, message + "")


def test_a_huge_image_is_refused_from_its_header(tmp_path):
    # 8000 x 8000 grey pixels: 64 million, below Pillow's bomb limit; 4 GB of working arrays
    image = tmp_path / "big.png"
    _png_header(image, 8000, 8000)
    _refused_in_subprocess(["generate", "map", "--image", str(image), "--metres-per-pixel", "0.05", "--kpois", "5"],
                           "big.png (8000 x 8000 pixels) needs about 4.1 GB of memory, more than the 50.0 MB")


def test_a_decompression_bomb_is_refused(tmp_path):
    # a 30000 x 30000 white image, in 100 bytes: matplotlib decoded it whatever its size
    image = tmp_path / "bomb.png"
    _png_header(image, 30000, 30000)
    _refused_in_subprocess(["generate", "map", "--image", str(image), "--metres-per-pixel", "0.05", "--kpois", "5"],
                           "bomb.png: refused as a possible decompression bomb: Image size (900000000 pixels)")


def test_an_image_array_is_counted_before_it_is_copied(monkeypatch):
    monkeypatch.setenv(memory.LIMIT_VARIABLE, "1MB")
    with pytest.raises(memory.MemoryLimitError, match="A map of 200 x 100 pixels needs about 1.4 MB"):
        read_free_mask(np.ones((100, 200, 3)))
    assert read_free_mask(np.ones((10, 20))).all()
    with pytest.raises(InputError, match=r"not shape \(5,\)"):
        read_free_mask(np.ones(5))


def test_an_instance_file_too_large_to_parse_is_refused(capsys, monkeypatch, tmp_path):
    path = tmp_path / "big.json"
    path.write_text(" " * 6_000_000)
    _refused(capsys, monkeypatch, ["solve", str(path)], "big.json (6.0 MB to parse) needs about 60.0 MB")


def test_a_map_of_many_kpois_is_refused_before_its_graph(capsys, monkeypatch, tmp_path):
    # one convex cell: every pair of 600 KPOIs would be an edge
    Image.fromarray(np.full((30, 30), 255, np.uint8)).save(tmp_path / "room.png")
    _refused(capsys, monkeypatch, ["generate", "map", "--image", str(tmp_path / "room.png"),
                                   "--metres-per-pixel", "0.1", "--kpois", "600"], "A map instance of 600 KPOIs needs")


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("random:n=100000:seeds=0..1000", "'random:n=100000:seeds=0..1000' (1001 instances) needs about 80.3 TB"),
        ("random:n=1..1000000000", "(1000000000 instances) needs about"),
        ("grid:rows=1..100000:cols=2..100000", "(9999900000 instances) needs about"),
        ("star:n=3..1500", "'star:n=3..1500' (1498 instances) needs about"),
    ],
)
def test_a_report_spec_too_large_is_refused_before_any_instance(capsys, monkeypatch, tmp_path, spec, message):
    started = time.monotonic()
    _refused(capsys, monkeypatch, ["report", spec, "--out", str(tmp_path / "r"), "--no-plots"], message)
    assert time.monotonic() - started < 5
    assert not (tmp_path / "r" / "gaps.csv").exists()


def test_a_report_grid_too_large_is_refused_before_any_solve(capsys, monkeypatch, tmp_path):
    robots = ",".join(str(k) for k in range(2, 3000))
    _refused(capsys, monkeypatch, ["report", "random:n=4:seeds=0..9", "--robots", robots, "--out", str(tmp_path),
                                   "--no-plots"], "A report of 10 instances x 2 route kinds x 2999 questions x 4 methods")
    assert not (tmp_path / "gaps.csv").exists()


def test_the_api_raises_input_error(monkeypatch):
    monkeypatch.setenv(memory.LIMIT_VARIABLE, CAP)
    with pytest.raises(InputError, match="A random instance of 5000 KPOIs"):
        generate.random_points(5000)
    assert generate.random_points(50).n == 50


# -- degenerate images: one line each ----------------------------------------------


def _image(path: Path, pixels: np.ndarray) -> str:
    Image.fromarray(pixels.astype(np.uint8)).save(path)
    return str(path)


@pytest.mark.parametrize(
    ("pixels", "message"),
    [
        (np.full((1, 1), 255), "The map's free space is too small to stand in"),  # was ValueError: high <= 0
        (np.pad(np.full((1, 1), 255), 9), "The map's free space is too small to stand in"),  # one free pixel
        (np.zeros((20, 20)), "The map has no free space."),
        (np.pad(np.full((2, 2), 255), 9), "Only 3 free pixels are reachable from the start; asked for 5 KPOIs."),
    ],
    ids=["1x1", "one-free-pixel", "all-black", "no-room-for-the-kpois"],
)
def test_a_degenerate_image_is_one_line(capsys, tmp_path, pixels, message):
    image = _image(tmp_path / "map.png", pixels)
    code = main(["generate", "map", "--image", image, "--metres-per-pixel", "0.05", "--kpois", "5"])
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.splitlines()) == 1, err


def test_a_folder_of_instances_is_counted_as_it_is_read(monkeypatch, tmp_path):
    # five instances of 400 KPOIs: each fits in 6 MB (4.3 MB to build, 1.7 MB kept), all do not
    from parcover.io import write_instance
    from parcover.report import load_instances

    for seed in range(5):
        write_instance(generate.random_points(400, seed), tmp_path / f"r{seed}.json")
    monkeypatch.setenv(memory.LIMIT_VARIABLE, "6MB")
    with pytest.raises(memory.MemoryLimitError, match="Loading the instances up to 'random-uniform-n400-s3' needs"):
        load_instances(tmp_path)
    monkeypatch.setenv(memory.LIMIT_VARIABLE, "10MB")
    assert len(load_instances(tmp_path)) == 5


def test_a_solve_too_large_for_its_working_memory_is_refused(capsys, monkeypatch, tmp_path):
    # 800 KPOIs: the instance (estimated 15 MB) fits under the 50 MB cap, the solver's
    # working memory (96 bytes an entry: 62 MB) does not; refused before the method starts.
    path = tmp_path / "r800.json"
    write_instance(generate.random_points(800, 1), path)
    _refused(capsys, monkeypatch, ["solve", str(path), "--method", "paper"], "Solving 800 KPOIs with paper needs about")
