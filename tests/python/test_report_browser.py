"""The report in a real browser: headless Chromium loads it without errors and draws it.

Negative controls prove the detector works: a page with a console error, an
exception and a missing image is caught, and a blank page is judged blank.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

import browser

WIDTH = 1280


def screenshot_stats(png: bytes) -> tuple[float, float]:
    """(pixel standard deviation, fraction of pixels that are not near-white) of a PNG."""
    import matplotlib.image

    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    rgb = matplotlib.image.imread(io.BytesIO(png), format="png")[..., :3]
    not_white = np.any(rgb < 0.94, axis=-1)
    return float(rgb.std()), float(not_white.mean())


def looks_blank(png: bytes) -> bool:
    std, ink = screenshot_stats(png)
    return std < 0.02 or ink < 0.01


def png_size(png: bytes) -> tuple[int, int]:
    """(width, height) from the PNG header."""
    return int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")


def test_report_loads_cleanly_and_is_drawn(chromium: str, identify_report: Path) -> None:
    r = browser.load_page(identify_report, width=WIDTH, chromium=chromium)
    assert r.errors == []
    assert len(r.images) == 6
    assert r.broken_images == []
    assert all(im["naturalWidth"] > 200 and im["naturalHeight"] > 200 for im in r.images)
    assert r.title.startswith("massid identification")
    assert r.scroll_width <= WIDTH  # no horizontal scrolling at 1280 px
    assert r.scroll_height > 3000  # six figures, tables and text
    width, height = png_size(r.screenshot)
    assert width == WIDTH and height == min(r.scroll_height, 16000)
    std, ink = screenshot_stats(r.screenshot)
    assert std > 0.05 and ink > 0.05, (std, ink)
    assert not looks_blank(r.screenshot)


def test_detector_catches_errors_and_broken_images(chromium: str, tmp_path: Path) -> None:
    page = tmp_path / "bad.html"
    page.write_text(
        '<!DOCTYPE html><html><head><meta charset="utf-8"><link rel="icon" href="data:,">'
        "<title>bad</title></head><body><h1>bad page</h1>"
        '<img src="missing.png" alt="missing">'
        '<script>console.error("x"); throw new Error("boom");</script>'
        "</body></html>", encoding="utf-8")
    r = browser.load_page(page, width=800, height=600, chromium=chromium)
    assert any(e.endswith(": x") for e in r.console), r.console
    assert any("boom" in e for e in r.exceptions), r.exceptions
    assert any("missing.png" in e for e in r.log_errors), r.log_errors
    assert len(r.broken_images) == 1 and r.broken_images[0]["src"] == "missing.png"
    assert len(r.errors) >= 3


def test_blank_page_is_judged_blank(chromium: str, tmp_path: Path) -> None:
    page = tmp_path / "blank.html"
    page.write_text('<!DOCTYPE html><html><head><meta charset="utf-8"><link rel="icon" href="data:,">'
                    "</head><body style=\"background:#fff\"></body></html>", encoding="utf-8")
    r = browser.load_page(page, width=800, height=600, chromium=chromium)
    assert r.errors == [] and r.images == []
    assert png_size(r.screenshot) == (800, 600)
    assert looks_blank(r.screenshot)
