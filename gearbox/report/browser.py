"""Open a report in headless Chromium and check that every figure decodes.

A copy of the report gets a small script that waits for the ``load`` event (which
waits for every image), counts the ``<img>`` elements that loaded with a non-zero
natural size and writes the counts into the DOM; Chromium's ``--dump-dom`` prints
that DOM. The report itself carries no script.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

__all__ = ["BrowserCheck", "browser_check", "find_chromium"]

_PROBE = """<script>
window.addEventListener("load", () => {
  const imgs = Array.from(document.images);
  const ok = imgs.filter((img) => img.complete && img.naturalWidth > 0 && img.naturalHeight > 0);
  const out = document.createElement("pre");
  out.id = "gearbox-browser-check";
  out.textContent = `images=${imgs.length} decoded=${ok.length} ` +
    `widths=${imgs.map((img) => img.naturalWidth).join(",")} ` +
    `title=${encodeURIComponent(document.title)}`;
  document.body.appendChild(out);
});
</script>"""

_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--no-first-run",
    "--disable-component-update",
    "--disable-sync",
    "--virtual-time-budget=10000",
    "--dump-dom",
)


@dataclass(frozen=True)
class BrowserCheck:
    """What Chromium saw: ``images`` in the page, ``decoded`` ones, their widths (px)."""

    images: int
    decoded: int
    widths: tuple[int, ...]
    title: str
    browser: str

    @property
    def ok(self) -> bool:
        return self.decoded == self.images


def find_chromium() -> str | None:
    """Path of a Chromium or Chrome executable on PATH, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


def browser_check(
    report: str | Path, *, chromium: str | None = None, timeout: float = 120
) -> BrowserCheck:
    """Render ``report`` in headless Chromium and count the images that decode.

    Raises ``FileNotFoundError`` when no Chromium is found and ``RuntimeError`` when
    Chromium does not produce the probe's output (its stderr tail in the message).
    """
    exe = chromium or find_chromium()
    if exe is None:
        raise FileNotFoundError("no chromium / chrome executable on PATH")
    html = Path(report).read_text(encoding="utf-8")
    probed = html.replace("</body>", _PROBE + "</body>", 1)
    with tempfile.TemporaryDirectory(prefix="gearbox-chromium-") as tmp:
        page = Path(tmp) / "report.html"
        page.write_text(probed, encoding="utf-8")
        profile = Path(tmp) / "profile"
        cmd = [exe, *_FLAGS, f"--user-data-dir={profile}", page.as_uri()]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    m = re.search(r"images=(\d+) decoded=(\d+) widths=([\d,]*) title=([^<\s]*)", proc.stdout)
    if m is None:
        tail = proc.stderr.strip().splitlines()[-5:]
        raise RuntimeError(f"chromium gave no result (exit {proc.returncode}): {' | '.join(tail)}")
    from urllib.parse import unquote

    widths = tuple(int(w) for w in m.group(3).split(",") if w)
    return BrowserCheck(int(m.group(1)), int(m.group(2)), widths, unquote(m.group(4)), exe)
