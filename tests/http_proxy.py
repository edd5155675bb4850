#!/usr/bin/python3
"""http_proxy.py — a fault-injecting HTTP proxy for the remote-file tests
(tests/cli_http.sh): forwards every request to UPSTREAM and spoils the
replies to range requests as MODE says, counted by request, never by time:

  pass         forwards everything unchanged
  drop N       closes the connection without an answer for the first N
               range requests, then forwards
  truncate N   sends the first N range replies with half their body (the
               headers promise all of it), then closes
  norange      strips the Range header (the server answers 200, the file)
  delay N      waits N/10 s before each reply (slow, never failing)
  etag N       from range request N on, answers with another ETag and
               another length in Content-Range (the file changed)
  etagonly N   from range request N on, answers with another ETag, the
               length and bytes intact (a file replaced by one of the same
               length: the ETag alone tells)
  newetag      while PORT_FILE.etag exists, every reply (HEAD too) carries
               another ETag, Last-Modified and length intact (the file
               replaced between two runs: a cache must not be trusted)
  novalid      strips ETag and Last-Modified from every reply (a server
               that gives no validators)
  crend N      from range request N on, answers a range one byte shorter
               than asked, its Content-Range saying so (a consistent reply,
               but not for the range asked)
  garble N     flips every bit of the body of range replies from N on
               (the length and headers intact: only the checksums can
               tell; every byte, so whatever part of a block is used)
  stall        answers the range requests past the metadata that do not
               end at the file's last byte (the chunks: what opening a
               file does not read; the metadata's end read from the .vsv
               header in the reply for byte 0) with their headers, then
               nothing: each held open until the proxy is killed (a server
               that stalls)
  stallopen    as stall, for every range request, the first included (a
               server that stalls before the file can be opened)
  stallflag    as stall while the file PORT_FILE.stall exists, else
               forwards (a server that stalls, then recovers)
  gzip N       from range request N on, sends the body gzip-compressed
               (Content-Encoding: gzip, Content-Length its length), the
               Content-Range unchanged: a server or proxy that compresses
               what was not asked to be
  down         closes the connection without an answer for every range
               request while the file PORT_FILE.down exists (the server
               gone), else forwards

Every range request is counted in PORT_FILE.count as it arrives.

Usage: http_proxy.py UPSTREAM_PORT PORT_FILE MODE [N]: listens on a free
loopback port, writes it to PORT_FILE, serves until killed.
"""
import gzip
import http.client
import http.server
import os
import sys
import threading
import time

UP = int(sys.argv[1])
MODE = sys.argv[3]
N = int(sys.argv[4]) if len(sys.argv) > 4 else 0
lock = threading.Lock()
count = [0]
meta_end = [None]  # stall: where the .vsv's metadata ends


class Handler(http.server.BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"

    def log_message(self, *a):
        pass

    def forward(self, head):
        rng = self.headers.get("Range")
        k = -1
        if rng:
            with lock:
                count[0] += 1
                k = count[0]
                with open(sys.argv[2] + ".count.tmp", "w") as f:
                    f.write(str(k))
                os.rename(sys.argv[2] + ".count.tmp", sys.argv[2] + ".count")
        gone = MODE == "down" and os.path.exists(sys.argv[2] + ".down")
        if k > 0 and ((MODE == "drop" and k <= N) or gone):
            self.close_connection = True
            self.connection.close()
            return
        c = http.client.HTTPConnection("127.0.0.1", UP, timeout=60)
        hdrs = {"Host": self.headers.get("Host", "localhost")}
        if rng and MODE != "norange":
            hdrs["Range"] = rng
        c.request("HEAD" if head else "GET", self.path, headers=hdrs)
        r = c.getresponse()
        body = r.read()
        c.close()
        if MODE == "delay":
            time.sleep(N / 10)
        out = dict(r.getheaders())
        if k > 0 and MODE == "etag" and k >= N:
            out["ETag"] = '"changed-%d"' % k
            cr = out.get("Content-Range", "")
            if "/" in cr:
                out["Content-Range"] = cr.split("/")[0] + "/" + str(int(cr.split("/")[1]) + 64)
        if (k > 0 and MODE == "etagonly" and k >= N) or (
            MODE == "newetag" and os.path.exists(sys.argv[2] + ".etag")
        ):
            for key in list(out):
                if key.lower() == "etag":
                    out[key] = out[key].rstrip('"') + '-new"'
        if MODE == "novalid":
            out = {key: v for key, v in out.items() if key.lower() not in ("etag", "last-modified")}
        if k > 0 and MODE == "crend" and k >= N and r.status == 206 and len(body) > 1:
            body = body[:-1]
            for key in list(out):
                if key.lower() == "content-range":  # bytes A-B/T: B one less
                    a_b, total = out[key].split("/")
                    a, b = a_b.split("-")
                    out[key] = "%s-%d/%s" % (a, int(b) - 1, total)
                elif key.lower() == "content-length":
                    out[key] = str(len(body))
        stalling = MODE == "stall" or (MODE == "stallflag" and os.path.exists(sys.argv[2] + ".stall"))
        if k > 0 and stalling and r.status == 206 and self.stalls(out, body):
            return
        if k > 0 and MODE == "stallopen" and r.status == 206:
            self.hold(out)
            return
        if k > 0 and MODE == "garble" and k >= N and body:
            body = bytes(b ^ 0xFF for b in body)
        if k > 0 and MODE == "gzip" and k >= N and body:
            body = gzip.compress(body)
            out = {key: v for key, v in out.items() if key.lower() != "content-length"}
            out["Content-Encoding"] = "gzip"
            out["Content-Length"] = str(len(body))
        cut = k > 0 and MODE == "truncate" and k <= N
        self.send_response_only(r.status, r.reason)
        for key, v in out.items():
            if key.lower() not in ("connection", "keep-alive", "transfer-encoding"):
                self.send_header(key, v)
        if cut:
            self.send_header("Connection", "close")
            self.close_connection = True
        self.end_headers()
        if not head:
            self.wfile.write(body[: len(body) // 2] if cut else body)
        self.wfile.flush()

    def stalls(self, out, body):
        """A reply for a range of chunks: its headers, then held."""
        cr = {key.lower(): v for key, v in out.items()}.get("content-range", "")
        try:
            a_b, total = cr.split(" ")[1].split("/")
            a, b = (int(x) for x in a_b.split("-"))
        except (IndexError, ValueError):
            return False
        if a == 0 and len(body) >= 40:  # the header: where the metadata ends
            with lock:
                meta_end[0] = int.from_bytes(body[24:32], "little") + int.from_bytes(body[32:40], "little")
        with lock:
            end = meta_end[0]
        if end is None or a < end or b == int(total) - 1:
            return False
        self.hold(out)
        return True

    def hold(self, out):
        """Sends the reply's headers, then nothing until the proxy is killed."""
        self.send_response_only(206, "Partial Content")
        for key, v in out.items():
            if key.lower() not in ("connection", "keep-alive", "transfer-encoding"):
                self.send_header(key, v)
        self.end_headers()
        self.wfile.flush()
        threading.Event().wait()  # until the proxy is killed

    def do_GET(self):
        self.forward(False)

    def do_HEAD(self):
        self.forward(True)


srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
srv.daemon_threads = True
with open(sys.argv[2] + ".tmp", "w") as f:
    f.write(str(srv.server_address[1]))
os.rename(sys.argv[2] + ".tmp", sys.argv[2])
srv.serve_forever()
