"""One headless Chromium for many page loads, driven over the DevTools protocol on a pipe
(--remote-debugging-pipe: JSON commands on the browser's file descriptor 3, replies and events on
4, each message ended by a NUL byte), with nothing but the standard library.

A browser start costs seconds (most of an animate:browser test when every page load was a browser
of its own); a page load in a running browser costs a fraction of one. Each load gets a fresh tab
(a new target: its own page, scripts and console), closed afterwards, so one page cannot see another.

    with Browser(chromium(), profile, 800, 600) as browser:
        page = browser.load(url)          # after the load event; page.dom, page.console
        page.screenshot(path)             # PNG of the 800x600 viewport
        page.close()
"""
import base64
import fcntl
import json
import os
import queue
import subprocess
import threading
import time

TIMEOUT = 120  # seconds for one command or one page load: a hang detector, not a speed limit


class BrowserError(RuntimeError):
    pass


class Page:
    def __init__(self, browser, target, session):
        self.browser, self.target, self.session = browser, target, session
        self.dom = ""

    @property
    def console(self):
        """The page's console and log entries, one line each: 'CONSOLE <level>: <text>'."""
        return list(self.browser.console.get(self.session, []))

    def evaluate(self, expression, await_promise=False):
        reply = self.browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                       "awaitPromise": await_promise}, self.session)
        if "exceptionDetails" in reply:
            raise BrowserError(f"{expression}: {reply['exceptionDetails'].get('text')}")
        return reply["result"].get("value")

    def screenshot(self, path):
        # Two animation frames first: what the page drew after its load is on the screen.
        self.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", await_promise=True)
        data = self.browser.call("Page.captureScreenshot", {"format": "png"}, self.session)["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def close(self):
        self.browser.call("Target.closeTarget", {"targetId": self.target})


class Browser:
    def __init__(self, binary, profile, width, height, arguments=()):
        self.width, self.height = width, height
        commands_read, self._commands = os.pipe()
        self._replies, replies_write = os.pipe()
        # The browser's descriptors 3 and 4, by way of the shell: copies above 10 first, so that
        # neither redirection overwrites the other's source.
        child_in = fcntl.fcntl(commands_read, fcntl.F_DUPFD, 10)
        child_out = fcntl.fcntl(replies_write, fcntl.F_DUPFD, 10)
        for fd in (commands_read, replies_write):
            os.close(fd)
        command = [binary, "--headless", "--no-sandbox", "--remote-debugging-pipe", f"--user-data-dir={profile}",
                   f"--window-size={width},{height}", "--hide-scrollbars", "--no-first-run",
                   "--disable-extensions", *arguments, "about:blank"]
        self.process = subprocess.Popen(
            ["bash", "-c", f'exec "$@" 3<&{child_in} 4>&{child_out} {child_in}<&- {child_out}>&-', "bash", *command],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(child_in, child_out))
        os.close(child_in)
        os.close(child_out)
        self._next_id = 0
        self._replies_by_id = {}
        self._messages = queue.Queue()
        self.console = {}  # session -> lines
        self._loaded = set()  # sessions whose load event came
        threading.Thread(target=self._read, daemon=True).start()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _read(self):
        buffer = b""
        while True:
            chunk = os.read(self._replies, 1 << 16)
            if not chunk:
                self._messages.put(None)
                return
            buffer += chunk
            *messages, buffer = buffer.split(b"\0")
            for message in messages:
                self._messages.put(json.loads(message))

    def _event(self, message):
        session, method, params = message.get("sessionId"), message.get("method"), message.get("params", {})
        lines = self.console.setdefault(session, [])
        if method == "Page.loadEventFired":
            self._loaded.add(session)
        elif method == "Runtime.consoleAPICalled":
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", []))
            lines.append(f"CONSOLE {params.get('type')}: {text}")
        elif method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            description = details.get("exception", {}).get("description") or details.get("text", "")
            lines.append(f"CONSOLE error: Uncaught {description}")
        elif method == "Log.entryAdded":
            entry = params.get("entry", {})
            lines.append(f"CONSOLE {entry.get('level')}: {entry.get('text')} ({entry.get('url', '')})")

    def _pump(self, deadline, done):
        """Handles messages until done() holds, or fails at the deadline."""
        while not done():
            try:
                message = self._messages.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise BrowserError("no answer from Chromium in time") from None
            if message is None:
                raise BrowserError(f"Chromium exited ({self.process.poll()})")
            if "id" in message:
                self._replies_by_id[message["id"]] = message
            else:
                self._event(message)

    def call(self, method, params=None, session=None):
        self._next_id += 1
        key = self._next_id
        message = {"id": key, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        data = json.dumps(message).encode() + b"\0"
        while data:
            data = data[os.write(self._commands, data):]
        self._pump(time.monotonic() + TIMEOUT, lambda: key in self._replies_by_id)
        reply = self._replies_by_id.pop(key)
        if "error" in reply:
            raise BrowserError(f"{method}: {reply['error'].get('message')}")
        return reply.get("result", {})

    def load(self, url):
        """A fresh tab showing url, after its load event; its DOM (as --dump-dom gives it) in .dom."""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        page = Page(self, target, session)
        for method in ("Page.enable", "Runtime.enable", "Log.enable"):
            self.call(method, session=session)
        self.call("Emulation.setDeviceMetricsOverride", {"width": self.width, "height": self.height,
                                                         "deviceScaleFactor": 1, "mobile": False}, session)
        self.call("Emulation.setScrollbarsHidden", {"hidden": True}, session)
        self.call("Page.navigate", {"url": url}, session)
        self._pump(time.monotonic() + TIMEOUT, lambda: session in self._loaded)
        page.dom = page.evaluate("document.documentElement.outerHTML")
        return page

    def close(self):
        try:
            self.call("Browser.close")
        except BrowserError:
            pass
        try:
            self.process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        os.close(self._commands)
