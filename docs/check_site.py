"""Checks of the built documentation site (build/docs/html; docs/CMakeLists.txt):

  links    every internal link and resource (href, src) of every page resolves to a file of the
           site, and every #fragment to an id of its page;
  browser  the index, the quickstart and the tutorial open in headless Chromium, served over HTTP from
           the site's directory, with no console error (MathJax typesets the tutorial); their screenshots go to OUT (the target docs-screenshots copies them to docs/site/).

Exit 77 (skipped) when the site was not built (cmake --build build --target docs) or, for browser,
when Chromium is missing."""
import argparse
import functools
import http.server
import html.parser
import pathlib
import shutil
import subprocess
import sys
import tempfile
import threading
import urllib.parse

SKIP = 77
PAGES = ["index.html", "quickstart.html", "tutorials/rolling_disk.html", "tutorials/control_lqr.html"]


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        for key, value in attrs:
            if key in ("id", "name") and value:
                self.ids.add(value)
            if key in ("href", "src") and value:
                self.links.append(value)


def parse(path):
    page = Page()
    page.feed(path.read_text(encoding="utf-8", errors="replace"))
    return page


def check_links(site):
    pages = sorted(site.rglob("*.html"))
    pages = [p for p in pages if "mathjax" not in p.relative_to(site).parts]
    parsed, broken, checked = {}, [], 0
    for page in pages:
        for link in parse(page).links:
            url = urllib.parse.urlsplit(link)
            if url.scheme or url.netloc or link.startswith(("mailto:", "javascript:", "data:")):
                continue
            target = (page.parent / urllib.parse.unquote(url.path)).resolve() if url.path else page
            if target.is_dir():
                target = target / "index.html"
            checked += 1
            if not target.exists():
                broken.append(f"{page.relative_to(site)}: {link} (no file {target})")
            elif url.fragment and target.suffix == ".html":
                if target not in parsed:
                    parsed[target] = parse(target).ids
                if urllib.parse.unquote(url.fragment) not in parsed[target]:
                    broken.append(f"{page.relative_to(site)}: {link} (no id '{url.fragment}' in {target.name})")
    for b in broken:
        print("broken:", b)
    print(f"{len(pages)} pages, {checked} internal links, {len(broken)} broken")
    return 1 if broken or checked < 100 else 0


def check_browser(site, out):
    browser = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)), None)
    if browser is None:
        print("skipped: Chromium is not installed (Debian: apt-get install chromium)")
        return SKIP
    out.mkdir(parents=True, exist_ok=True)
    failures = 0
    # Served over HTTP, as a reader's browser gets a published site (from file:// Chromium blocks
    # MathJax's font probes as cross-origin requests).
    missing = []  # every request the site could not answer (Chromium's own /favicon.ico aside)

    class Handler(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass

        def send_error(self, code, message=None, explain=None):
            if not self.path.startswith("/favicon.ico"):
                missing.append(f"{code} {self.path}")
            super().send_error(code, message, explain)

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Handler, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    with tempfile.TemporaryDirectory() as profile:
        for name in PAGES:
            url = base + name
            shot = out / (name.replace("/", "-").replace(".html", ".png"))
            command = [browser, "--headless", "--no-sandbox", "--hide-scrollbars", "--window-size=1200,900",
                       f"--user-data-dir={profile}", "--enable-logging=stderr", "--v=0", "--no-first-run",
                       "--disable-extensions", "--virtual-time-budget=5000"]
            dom = subprocess.run(command + ["--dump-dom", url], capture_output=True, text=True, timeout=120)
            subprocess.run(command + [f"--screenshot={shot}", url], capture_output=True, text=True, timeout=120)
            console = [line for line in dom.stderr.splitlines() if "CONSOLE" in line]
            errors = [line for line in console
                      if any(w in line for w in ("rror", "Uncaught", "Failed", "blocked", "404", "Warning"))]
            errors += [f"the server answered {m}" for m in missing]
            missing.clear()
            if dom.returncode != 0 or "<article role=\"main\"" not in dom.stdout:
                errors.append(f"Chromium exited with {dom.returncode} and no page content: {dom.stderr[-400:]}")
            if not shot.exists() or shot.stat().st_size < 10000:
                errors.append(f"no screenshot in {shot}")
            # MathJax typesets the page: its output elements are in the DOM (no CDN: the site's own copy).
            if name.startswith("tutorials/") and "MathJax" not in dom.stdout:
                errors.append("MathJax did not typeset the page")
            print(f"{name}: {len(console)} console lines, {len(errors)} errors, screenshot {shot.name}")
            for e in errors:
                print("  ", e)
            if errors:
                failures += 1
    server.shutdown()
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("check", choices=["links", "browser"])
    parser.add_argument("--site", type=pathlib.Path, required=True)
    parser.add_argument("--out", type=pathlib.Path)
    args = parser.parse_args()
    if not (args.site / "index.html").exists():
        print(f"skipped: the site was not built ({args.site}/index.html; cmake --build build --target docs)")
        return SKIP
    return check_links(args.site) if args.check == "links" else check_browser(args.site, args.out)


if __name__ == "__main__":
    sys.exit(main())
