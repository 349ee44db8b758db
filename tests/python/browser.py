"""Load a page in headless Chromium and report what a person would see.

Drives Debian's /usr/bin/chromium through the Chrome DevTools Protocol over
``--remote-debugging-pipe`` (fd 3: commands to Chrome, fd 4: its replies and
events; each message is JSON followed by a NUL byte). Standard library only.

    result = load_page("report.html")
    result.errors          # console errors/warnings, exceptions, failed loads
    result.broken_images   # <img> elements that did not load
    result.screenshot      # full-page PNG (bytes)

As a script (used to make docs/report_puma260.png)::

    python3 tests/python/browser.py report.html -o shot.png [--width 1280] [--max-height 20000]
"""

from __future__ import annotations

import argparse
import base64
import json
import os
import queue
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

CHROMIUM = "/usr/bin/chromium"
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
    "--mute-audio",
    "--remote-debugging-pipe",
]

# Collected in the page once it has loaded: every image's state and the page size.
_PAGE_STATE_JS = """JSON.stringify({
  images: Array.from(document.images).map(function (im) {
    return {src: (im.getAttribute('src') || '').slice(0, 80), complete: im.complete,
            naturalWidth: im.naturalWidth, naturalHeight: im.naturalHeight};
  }),
  scrollHeight: Math.max(document.body ? document.body.scrollHeight : 0,
                         document.documentElement.scrollHeight),
  scrollWidth: document.documentElement.scrollWidth,
  title: document.title,
  text: document.body ? document.body.innerText.length : 0
})"""


class BrowserError(RuntimeError):
    """Chromium could not be started, exited, or did not answer in time."""


@dataclass
class PageResult:
    """What loading a page produced."""

    url: str
    console: list[str] = field(default_factory=list)  # console.error / console.warn / assert
    exceptions: list[str] = field(default_factory=list)  # uncaught exceptions
    log_errors: list[str] = field(default_factory=list)  # Log domain errors (failed loads, ...)
    images: list[dict[str, Any]] = field(default_factory=list)
    scroll_height: int = 0
    scroll_width: int = 0
    title: str = ""
    text_length: int = 0
    screenshot: bytes = b""

    @property
    def errors(self) -> list[str]:
        """Every problem a person would see in the developer console."""
        return self.console + self.exceptions + self.log_errors

    @property
    def broken_images(self) -> list[dict[str, Any]]:
        """Images that are not complete or have no pixels."""
        return [im for im in self.images if not im["complete"] or im["naturalWidth"] <= 0]


class _Pipe:
    """The DevTools protocol over Chromium's pipe: numbered commands and queued events."""

    def __init__(self, write_fd: int, read_fd: int) -> None:
        self._w = os.fdopen(write_fd, "wb", buffering=0)
        self._r = os.fdopen(read_fd, "rb", buffering=0)
        self._next = 0
        self._replies: dict[int, dict[str, Any]] = {}
        self._events: "queue.Queue[dict[str, Any]]" = queue.Queue()
        self._cond = threading.Condition()
        self._closed = False
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        buf = b""
        try:
            while True:
                chunk = self._r.read(65536)
                if not chunk:
                    break
                buf += chunk
                while b"\0" in buf:
                    raw, buf = buf.split(b"\0", 1)
                    msg = json.loads(raw.decode("utf-8"))
                    if "id" in msg:
                        with self._cond:
                            self._replies[msg["id"]] = msg
                            self._cond.notify_all()
                    else:
                        self._events.put(msg)
        except (OSError, ValueError):
            pass
        finally:
            with self._cond:
                self._closed = True
                self._cond.notify_all()

    def send(self, method: str, params: Optional[dict[str, Any]] = None,
             session: Optional[str] = None, deadline: float = 0.0) -> dict[str, Any]:
        """Send one command and wait for its reply (raise BrowserError on error or timeout)."""
        self._next += 1
        cid = self._next
        msg: dict[str, Any] = {"id": cid, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        try:
            self._w.write(json.dumps(msg).encode("utf-8") + b"\0")
        except OSError as e:
            raise BrowserError(f"chromium closed its pipe ({method}): {e}") from e
        with self._cond:
            while cid not in self._replies:
                left = deadline - time.monotonic()
                if self._closed:
                    raise BrowserError(f"chromium exited while waiting for {method}")
                if left <= 0:
                    raise BrowserError(f"no reply to {method} in time")
                self._cond.wait(min(left, 0.5))
            reply = self._replies.pop(cid)
        if "error" in reply:
            raise BrowserError(f"{method}: {reply['error'].get('message', reply['error'])}")
        return reply.get("result", {})

    def event(self, timeout: float) -> Optional[dict[str, Any]]:
        try:
            return self._events.get(timeout=max(0.0, timeout))
        except queue.Empty:
            return None

    def close(self) -> None:
        for f in (self._w, self._r):
            try:
                f.close()
            except OSError:
                pass


def chromium_available(path: str = CHROMIUM) -> bool:
    """True when the Chromium binary exists and is executable."""
    return os.path.isfile(path) and os.access(path, os.X_OK)


def _describe_console(params: dict[str, Any]) -> str:
    args = params.get("args", [])
    text = " ".join(str(a.get("value", a.get("description", a.get("type", "")))) for a in args)
    return f"console.{params.get('type')}: {text}"


def _describe_exception(params: dict[str, Any]) -> str:
    d = params.get("exceptionDetails", {})
    exc = d.get("exception", {})
    return f"exception: {exc.get('description') or d.get('text', '')}"


def load_page(page: os.PathLike[str] | str, *, width: int = 1280, height: int = 800,
              full_page: bool = True, max_height: int = 16000, timeout: float = 60.0,
              chromium: str = CHROMIUM) -> PageResult:
    """Open a local HTML file in headless Chromium and collect errors, images and a screenshot.

    Args:
        page: the HTML file.
        width, height: the viewport in CSS pixels (device scale 1).
        full_page: screenshot the whole page (up to max_height pixels), not the viewport.
        timeout: seconds for the whole run; BrowserError when exceeded.
        chromium: the browser binary.

    Chromium runs in its own process group with a fresh profile directory, and
    is killed (the whole group) when this returns or raises.
    """
    url = Path(page).resolve().as_uri()
    deadline = time.monotonic() + timeout
    result = PageResult(url=url)
    with tempfile.TemporaryDirectory(prefix="massid-chromium-") as profile:
        to_chrome_r, to_chrome_w = os.pipe()
        from_chrome_r, from_chrome_w = os.pipe()

        def child_fds() -> None:  # in the child: its fd 3 reads commands, fd 4 writes replies
            a, b = os.dup(to_chrome_r), os.dup(from_chrome_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        cmd = [chromium, *FLAGS, f"--user-data-dir={profile}", f"--window-size={width},{height}",
               "about:blank"]
        try:
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL, pass_fds=(3, 4, to_chrome_r, from_chrome_w),
                                    preexec_fn=child_fds, start_new_session=True)
        except OSError as e:
            for fd in (to_chrome_r, to_chrome_w, from_chrome_r, from_chrome_w):
                os.close(fd)
            raise BrowserError(f"cannot start {chromium}: {e}") from e
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        pipe = _Pipe(to_chrome_w, from_chrome_r)
        try:
            _drive(pipe, url, result, width, height, full_page, max_height, deadline)
            try:
                pipe.send("Browser.close", deadline=min(deadline, time.monotonic() + 3.0))
            except BrowserError:
                pass
        finally:
            pipe.close()
            try:
                proc.wait(timeout=3.0)
            except subprocess.TimeoutExpired:
                pass
            # Chromium's helpers (zygote, renderer) are in its process group, which
            # start_new_session made: kill the group, whether or not the browser exited.
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
            try:
                proc.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                pass
    return result


def _drive(pipe: _Pipe, url: str, result: PageResult, width: int, height: int,
           full_page: bool, max_height: int, deadline: float) -> None:
    target = pipe.send("Target.createTarget", {"url": "about:blank"}, deadline=deadline)["targetId"]
    session = pipe.send("Target.attachToTarget", {"targetId": target, "flatten": True},
                        deadline=deadline)["sessionId"]

    def send(method: str, params: Optional[dict[str, Any]] = None) -> dict[str, Any]:
        return pipe.send(method, params, session=session, deadline=deadline)

    for domain in ("Runtime", "Log", "Page"):
        send(f"{domain}.enable")
    send("Emulation.setDeviceMetricsOverride",
         {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
    nav = send("Page.navigate", {"url": url})
    if nav.get("errorText"):
        raise BrowserError(f"cannot load {url}: {nav['errorText']}")

    def take(ev: dict[str, Any]) -> bool:
        """Record one event; True for this page's load event."""
        if ev.get("sessionId") != session:
            return False
        method, params = ev.get("method"), ev.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "warning", "assert"):
            result.console.append(_describe_console(params))
        elif method == "Runtime.exceptionThrown":
            result.exceptions.append(_describe_exception(params))
        elif method == "Log.entryAdded":
            entry = params.get("entry", {})
            if entry.get("level") == "error":
                result.log_errors.append(f"{entry.get('source')}: {entry.get('text')} {entry.get('url', '')}".strip())
        return method == "Page.loadEventFired"

    loaded = False
    while not loaded:
        left = deadline - time.monotonic()
        if left <= 0:
            raise BrowserError(f"{url} did not finish loading in time")
        ev = pipe.event(min(left, 0.5))
        if ev is not None:
            loaded = take(ev)
    # Late console messages and failed loads: drain events for a moment.
    settle = time.monotonic() + 0.3
    while time.monotonic() < settle:
        ev = pipe.event(0.05)
        if ev is not None:
            take(ev)

    state = json.loads(send("Runtime.evaluate", {"expression": _PAGE_STATE_JS,
                                                 "returnByValue": True})["result"]["value"])
    result.images = state["images"]
    result.scroll_height = int(state["scrollHeight"])
    result.scroll_width = int(state["scrollWidth"])
    result.title = state["title"]
    result.text_length = int(state["text"])

    shot_height = min(max(result.scroll_height, height), max_height) if full_page else height
    if shot_height != height:
        send("Emulation.setDeviceMetricsOverride",
             {"width": width, "height": shot_height, "deviceScaleFactor": 1, "mobile": False})
    shot = send("Page.captureScreenshot",
                {"format": "png", "captureBeyondViewport": False,
                 "clip": {"x": 0, "y": 0, "width": width, "height": shot_height, "scale": 1}})
    result.screenshot = base64.b64decode(shot["data"])
    while True:  # anything logged while taking the screenshot
        ev = pipe.event(0.0)
        if ev is None:
            break
        take(ev)


def main(argv: Optional[list[str]] = None) -> int:
    """Screenshot a page and print what went wrong in it (exit 1 if anything did)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("page")
    ap.add_argument("-o", "--output", help="the full-page screenshot (PNG)")
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--max-height", type=int, default=16000)
    args = ap.parse_args(argv)
    r = load_page(args.page, width=args.width, max_height=args.max_height)
    if args.output:
        Path(args.output).write_bytes(r.screenshot)
    print(f"{r.url}: {len(r.images)} images, page {r.scroll_width} x {r.scroll_height} px, "
          f"{len(r.errors)} errors, {len(r.broken_images)} broken images")
    for e in r.errors:
        print("  " + e)
    return 1 if r.errors or r.broken_images else 0


if __name__ == "__main__":
    sys.exit(main())
