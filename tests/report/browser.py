"""Headless Chromium driven over the DevTools protocol on a pipe (no extra packages).

``chromium --remote-debugging-pipe`` reads JSON commands on fd 3 and writes
replies and events on fd 4, each message ending in a NUL byte (the transport
Puppeteer's ``pipe: true`` uses). That is enough to load report.html, run
JavaScript in it (awaiting promises: a video's metadata), read what the console
said, click, and take screenshots, without a Python DevTools client package.

    with Chromium(profile_dir) as browser:
        page = browser.open(path, width=1280, height=900)
        page.js("document.title")
        page.screenshot(png_path)
"""

from __future__ import annotations

import base64
import json
import os
import select
import shutil
import subprocess
import time
from pathlib import Path
from typing import Any

EXE = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists()
                                   else None)
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-sync",
         "--disable-background-networking", "--disable-component-update", "--mute-audio",
         "--hide-scrollbars", "--remote-debugging-pipe"]


class Chromium:
    """One headless browser; ``open`` gives a page."""

    def __init__(self, profile: Path, timeout: float = 60.0) -> None:
        """Start Chromium with its own profile folder; commands time out after ``timeout`` s."""
        assert EXE is not None, "chromium is not installed"
        self.timeout = timeout
        ours_r, theirs_w = os.pipe()  # Chromium writes replies on its fd 4
        theirs_r, ours_w = os.pipe()  # ... and reads commands on its fd 3

        def fds() -> None:  # in the child: copies first, in case a pipe end is fd 3 or 4
            r, w = os.dup(theirs_r), os.dup(theirs_w)
            os.dup2(r, 3)
            os.dup2(w, 4)

        # pass_fds keeps 3 and 4 open: the child closes other descriptors after preexec_fn.
        self.proc = subprocess.Popen([EXE, *FLAGS, f"--user-data-dir={profile}", "about:blank"],
                                     pass_fds=(3, 4), preexec_fn=fds,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(theirs_r)
        os.close(theirs_w)
        self.rfd, self.wfd = ours_r, ours_w
        self.buffer, self.next_id = b"", 0
        self.events: list[dict[str, Any]] = []

    def __enter__(self) -> Chromium:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def close(self) -> None:
        """Ask the browser to quit; kill it if it does not."""
        try:
            self.send("Browser.close")
        except (OSError, RuntimeError, TimeoutError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self.rfd, self.wfd):
            try:
                os.close(fd)
            except OSError:
                pass

    # -- the protocol ----------------------------------------------------------------------
    def send(self, method: str, params: dict | None = None, session: str | None = None) -> dict:
        """Send one command and wait for its reply (events on the way are kept)."""
        self.next_id += 1
        message: dict[str, Any] = {"id": self.next_id, "method": method, "params": params or {}}
        if session is not None:
            message["sessionId"] = session
        os.write(self.wfd, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + self.timeout
        while True:
            reply = self._read(deadline)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            if "method" in reply:
                self.events.append(reply)

    def wait_event(self, method: str, session: str, after: int) -> dict:
        """The first event ``method`` of ``session`` among events number ``after`` on."""
        deadline = time.monotonic() + self.timeout
        while True:
            for event in self.events[after:]:
                if event["method"] == method and event.get("sessionId") == session:
                    return event
            after = len(self.events)
            message = self._read(deadline)
            if "method" in message:
                self.events.append(message)

    def _read(self, deadline: float) -> dict:
        """The next whole message from the browser."""
        while b"\0" not in self.buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self.rfd], [], [], left)[0]:
                raise TimeoutError("no reply from chromium")
            chunk = os.read(self.rfd, 1 << 20)
            if not chunk:
                raise RuntimeError("chromium closed the pipe")
            self.buffer += chunk
        raw, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(raw)

    def open(self, path: Path, width: int = 1280, height: int = 900) -> Page:
        """Load a file in a new tab of ``width`` x ``height`` CSS px; wait for its load event."""
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})
        page = Page(self, session["sessionId"])
        page.send("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
        for domain in ("Runtime", "Log", "Page"):
            page.send(f"{domain}.enable")
        mark = len(self.events)
        page.send("Page.navigate", {"url": path.resolve().as_uri()})
        self.wait_event("Page.loadEventFired", page.session, mark)
        return page


class Page:
    """One tab: run JavaScript, collect console problems, click, take screenshots."""

    def __init__(self, browser: Chromium, session: str) -> None:
        self.browser, self.session = browser, session

    def send(self, method: str, params: dict | None = None) -> dict:
        """A command for this tab."""
        return self.browser.send(method, params, self.session)

    def js(self, expression: str) -> Any:
        """Evaluate ``expression`` (awaiting a promise) and return its value as JSON data."""
        reply = self.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                               "returnByValue": True})
        if "exceptionDetails" in reply:
            raise RuntimeError(f"{expression[:80]}: {reply['exceptionDetails']}")
        return reply["result"].get("value")

    def problems(self) -> list[str]:
        """Console errors and warnings, uncaught exceptions and failed loads, so far."""
        out = []
        for event in self.browser.events:
            if event.get("sessionId") != self.session:
                continue
            method, params = event["method"], event.get("params", {})
            if method == "Runtime.exceptionThrown":
                details = params["exceptionDetails"]
                out.append(details.get("exception", {}).get("description", details["text"]))
            elif method == "Runtime.consoleAPICalled" and params["type"] in ("error", "warning"):
                out.append(" ".join(str(a.get("value", a.get("description")))
                                    for a in params["args"]))
            elif method == "Log.entryAdded" and params["entry"]["level"] in ("error", "warning"):
                out.append(params["entry"]["text"])
        return out

    def click(self, selector: str) -> None:
        """Click the element ``selector`` matches (a DOM click event)."""
        self.js(f"document.querySelector({json.dumps(selector)}).click()")

    def screenshot(self, path: Path, selector: str | None = None, scale: float = 1.0) -> bytes:
        """A PNG of the whole page, or of the element ``selector`` matches."""
        box = "document.documentElement" if selector is None else \
            f"document.querySelector({json.dumps(selector)})"
        r = self.js(f"(() => {{ const e = {box}; const b = e.getBoundingClientRect(); "
                    "return [b.left + scrollX, b.top + scrollY, "
                    "Math.max(b.width, e.scrollWidth), Math.max(b.height, e.scrollHeight)]; })()")
        clip = {"x": r[0], "y": r[1], "width": r[2], "height": r[3], "scale": scale}
        data = base64.b64decode(self.send("Page.captureScreenshot", {
            "format": "png", "clip": clip, "captureBeyondViewport": True})["data"])
        path.write_bytes(data)
        return data
