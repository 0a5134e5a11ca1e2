"""docs/gallery.md: its generator runs, and the page shows every picture it draws."""

import re
import runpy
from pathlib import Path

DOCS = Path(__file__).parent.parent / "docs"


def test_the_gallery_generator_draws_every_picture_of_the_page(tmp_path):
    gallery = runpy.run_path(str(DOCS / "make_gallery.py"))
    written = gallery["main"](tmp_path / "gallery")
    names = [p.name for p in written]
    assert names == list(gallery["PICTURES"])
    for path in written:
        data = path.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and 5_000 < len(data) < 200_000  # drawn, and small
    shown = re.findall(r"!\[[^\]]+\]\(gallery/([^)]+)\)", (DOCS / "gallery.md").read_text())
    assert shown == names  # one picture of each kind, in order, none missing
    assert all((DOCS / "gallery" / name).exists() for name in names)  # committed
