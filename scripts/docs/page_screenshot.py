#!/usr/bin/python3
"""Screenshots of a live page (one that keeps streaming, such as `juggle play`'s) in headless
Chromium, driven over the DevTools protocol on a pipe (--remote-debugging-pipe: no WebSocket
library needed). Chromium's own --screenshot fires at the load event, before a stream's first
frames; this waits the given seconds first.

  scripts/docs/page_screenshot.py URL OUT.png [--wait=6] [--size=1200x760] [--keys=KEYS]

--keys: characters typed into the page (one key event each, 0.3 s apart) after the wait,
then another wait before the shot (e.g. "3" chooses the third skill on the live page).
"""
import argparse
import base64
import json
import os
import subprocess
import sys
import tempfile
import time


class Pipe:
    def __init__(self, write_fd, read_fd):
        self.w, self.r, self.buf, self.next_id = write_fd, read_fd, b"", 1

    def send(self, method, params=None, session=None):
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        self.next_id += 1
        os.write(self.w, json.dumps(message).encode() + b"\0")
        return self.wait(message["id"])

    def wait(self, message_id):
        while True:
            while b"\0" not in self.buf:
                chunk = os.read(self.r, 1 << 20)
                if not chunk:
                    raise RuntimeError("chromium closed the pipe")
                self.buf += chunk
            raw, self.buf = self.buf.split(b"\0", 1)
            message = json.loads(raw)
            if message.get("id") == message_id:
                if "error" in message:
                    raise RuntimeError(message["error"])
                return message.get("result", {})


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("url")
    parser.add_argument("out")
    parser.add_argument("--wait", type=float, default=6)
    parser.add_argument("--size", default="1200x760")
    parser.add_argument("--keys", default="")
    a = parser.parse_args()
    width, height = (int(v) for v in a.size.split("x"))
    to_chrome_r, to_chrome_w = os.pipe()
    from_chrome_r, from_chrome_w = os.pipe()
    profile = tempfile.mkdtemp(prefix="juggle_shot_")

    def child_fds():  # chromium reads commands on fd 3 and writes answers on fd 4
        r, w = os.dup(to_chrome_r), os.dup(from_chrome_w)  # above 4: no clash while moving
        os.dup2(r, 3)
        os.dup2(w, 4)

    chrome = subprocess.Popen(
        ["chromium", "--headless", "--no-sandbox", "--use-gl=swiftshader",
         "--enable-unsafe-swiftshader", "--hide-scrollbars", "--remote-debugging-pipe",
         f"--user-data-dir={profile}", f"--window-size={width},{height}", a.url],
        preexec_fn=child_fds, close_fds=False,
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(to_chrome_r)
    os.close(from_chrome_w)
    pipe = Pipe(to_chrome_w, from_chrome_r)
    try:
        targets = pipe.send("Target.getTargets")["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        session = pipe.send("Target.attachToTarget",
                            {"targetId": page["targetId"], "flatten": True})["sessionId"]
        time.sleep(a.wait)
        if a.keys:
            for key in a.keys:
                for kind in ("keyDown", "keyUp"):
                    pipe.send("Input.dispatchKeyEvent",
                              {"type": kind, "key": key, "text": key if kind == "keyDown" else ""},
                              session)
                time.sleep(0.3)
            time.sleep(a.wait)
        shot = pipe.send("Page.captureScreenshot", {"format": "png"}, session)
        with open(a.out, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        print(f"wrote {a.out}")
    finally:
        chrome.kill()
        chrome.wait()
        subprocess.run(["rm", "-rf", profile])


if __name__ == "__main__":
    sys.exit(main())
