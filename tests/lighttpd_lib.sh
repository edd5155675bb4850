# lighttpd_lib.sh — a real web server on the loopback interface for the
# HTTP tests and benchmarks (tests/cli_http.sh, bench/bench_http.sh). Sourced
# after the caller has set T (a scratch folder: the server serves $T/www),
# PY (a python3) and server_down MESSAGE (what to do when lighttpd will not
# start). LIGHTTPD is empty when lighttpd is not installed.
LIGHTTPD=$(command -v lighttpd 2> /dev/null || echo /usr/sbin/lighttpd)
[ -x "$LIGHTTPD" ] || LIGHTTPD=
LPID=
PORT=
stop_server() { [ -n "$LPID" ] && kill -INT "$LPID" 2> /dev/null && wait "$LPID" 2> /dev/null; LPID=; }
# free_port: a port nothing listens on now (the server retries if taken)
free_port() { "$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
# listening PORT: waits (bounded) until something accepts on PORT
listening() {
    "$PY" - "$1" <<'PYEOF'
import socket, sys, time
for _ in range(300):
    try:
        socket.create_connection(("127.0.0.1", int(sys.argv[1])), 1).close()
        sys.exit(0)
    except OSError:
        time.sleep(0.1)
sys.exit(1)
PYEOF
}
# start_server [ssl]: lighttpd serving $T/www on a free port ($PORT: the
# one before, if still free: the cache knows a file by its URL), its access
# log $T/access.log: request, status, body bytes sent. ssl: HTTPS with
# $T/cert.pem and $T/key.pem.
start_server() {
    for try in 1 2 3 4 5; do
        [ -n "$PORT" ] && [ $try = 1 ] || PORT=$(free_port)
        {
            echo "server.document-root = \"$T/www\""
            echo "server.bind = \"127.0.0.1\""
            echo "server.port = $PORT"
            echo "server.modules = (\"mod_accesslog\"$([ "${1:-}" = ssl ] && echo ', "mod_openssl"'))"
            echo "accesslog.filename = \"$T/access.log\""
            echo 'accesslog.format = "%r %s %b"'
            echo "server.errorlog = \"$T/error.log\""
            # a MIME type for .vsv: without one lighttpd sends no ETag and
            # no Last-Modified, and a cache cannot be validated
            echo 'mimetype.assign = ("" => "application/octet-stream")'
            if [ "${1:-}" = ssl ]; then
                echo 'ssl.engine = "enable"'
                echo "ssl.pemfile = \"$T/cert.pem\""
                echo "ssl.privkey = \"$T/key.pem\""
            fi
        } > "$T/lighttpd.conf"
        : > "$T/access.log"
        "$LIGHTTPD" -D -f "$T/lighttpd.conf" > "$T/lighttpd.out" 2>&1 &
        LPID=$!
        listening "$PORT" && kill -0 "$LPID" 2> /dev/null && return 0
        stop_server
    done
    server_down "$(cat "$T/lighttpd.out" "$T/error.log" 2> /dev/null | head -c 300)"
}
# body_bytes: the bytes the server sent in bodies (the log is complete once
# the server has stopped)
body_bytes() { awk '{ n += $NF } END { print n + 0 }' "$T/access.log"; }
