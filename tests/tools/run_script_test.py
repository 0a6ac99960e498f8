#!/usr/bin/env python3
"""Test driver for the semgraph command-line tool (registered by tests/tools/CMakeLists.txt).

  run_script_test.py run   TOOL SCRIPT PREFIX   `TOOL run SCRIPT`, checked against PREFIX.*
  run_script_test.py stdin TOOL SCRIPT PREFIX   the same, with the script on stdin (`-`)
  run_script_test.py dot   TOOL SCRIPT [DOT]    `TOOL dot SCRIPT` is DOT that `DOT -Tsvg` renders
                                                (exit 77 = skipped when DOT is not given)
  run_script_test.py export TOOL SCRIPT         `TOOL export SCRIPT` is a script that `TOOL run`
                                                applies without an error, and whose own export
                                                is itself (a fixed point)
  run_script_test.py cli   TOOL                 --help, --version, run/dot/export --help, usage errors,
                                                unreadable files, hostile
                                                input (huge, deeply nested, not UTF-8, alias
                                                bombs), output failures, out of memory

Expectations of a script (PREFIX = scripts/NAME):
  PREFIX.expected_exit     the exit code (default 0)
  PREFIX.expected.jsonl    stdout, one JSON object per line; required unless the exit is 2
  PREFIX.expected_stderr   each non-empty line must occur in stderr (e.g. `NAME.yaml:3:5:`)
Exit 2 (malformed) also requires an empty stdout and a FILE:LINE:COLUMN: message on stderr.

stdout is compared line by line: the text with every number replaced by `#` must be identical
(this pins the exact format: keys, order, spacing, escapes), and the numbers must agree within
1e-9 (relative to max(1, |expected|)), so that expected values can come from an independent
computation rather than from the tool. A quaternion with w == 0 may come with either sign.
"""
import json
import os
import re
import subprocess
import sys

TOLERANCE = 1e-9
NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read(path, default=None):
    if not os.path.exists(path):
        return default
    with open(path, encoding="utf-8") as f:
        return f.read()


def strict_json(line):
    def reject(constant):
        raise ValueError("non-JSON constant " + constant)
    return json.loads(line, parse_constant=reject)


def numbers_close(actual, expected):
    return abs(actual - expected) <= TOLERANCE * max(1.0, abs(expected))


def values_match(actual, expected, key):
    if isinstance(expected, bool) or isinstance(expected, str) or expected is None:
        return type(actual) is type(expected) and actual == expected
    if isinstance(expected, (int, float)):
        return isinstance(actual, (int, float)) and not isinstance(actual, bool) and \
            numbers_close(actual, expected)
    if isinstance(expected, list):
        if not isinstance(actual, list) or len(actual) != len(expected):
            return False
        if all(values_match(a, e, None) for a, e in zip(actual, expected)):
            return True
        # q and -q are one rotation; the sign is only ambiguous when w is (numerically) 0.
        if key == "quaternion" and abs(expected[0]) <= TOLERANCE:
            return all(values_match(a, -e, None) for a, e in zip(actual, expected))
        return False
    if isinstance(expected, dict):  # e.g. a repair's "discrepancy": same keys, values match
        return isinstance(actual, dict) and list(actual.keys()) == list(expected.keys()) and \
            all(values_match(actual[k], expected[k], k) for k in expected)
    return False


def compare_jsonl(actual_text, expected_text):
    # Lines end at "\n" only (str.splitlines would also split at U+0085, U+2028, ...).
    actual = actual_text.split("\n")
    if actual and actual[-1] == "":
        actual.pop()
    expected = [line for line in expected_text.split("\n") if line.strip()]
    if len(actual) != len(expected):
        fail("stdout has %d lines, expected %d:\n%s" % (len(actual), len(expected), actual_text))
    for n, (a_line, e_line) in enumerate(zip(actual, expected)):
        try:
            a = strict_json(a_line)
        except ValueError as e:
            fail("line %d is not JSON (%s): %s" % (n + 1, e, a_line))
        e_obj = strict_json(e_line)
        if NUMBER.sub("#", a_line) != NUMBER.sub("#", e_line):
            fail("line %d differs in format:\n  actual:   %s\n  expected: %s" % (n + 1, a_line, e_line))
        if list(a.keys()) != list(e_obj.keys()) or \
                not all(values_match(a[k], e_obj[k], k) for k in e_obj):
            fail("line %d differs:\n  actual:   %s\n  expected: %s" % (n + 1, a_line, e_line))


def run_tool(args, stdin_path=None, input_bytes=None):
    if input_bytes is not None:
        p = subprocess.run(args, input=input_bytes, capture_output=True, timeout=120)
    else:
        stdin = open(stdin_path, "rb") if stdin_path else subprocess.DEVNULL
        try:
            p = subprocess.run(args, stdin=stdin, capture_output=True, timeout=120)
        finally:
            if stdin_path:
                stdin.close()
    return p.returncode, p.stdout.decode("utf-8"), p.stderr.decode("utf-8", "replace")


def check_script(tool, script, prefix, use_stdin):
    if use_stdin:
        code, out, err = run_tool([tool, "run", "-"], stdin_path=script)
    else:
        code, out, err = run_tool([tool, "run", script])
    expected_exit = int((read(prefix + ".expected_exit", "0")).strip())
    if code != expected_exit:
        fail("exit code %d, expected %d\nstdout:\n%s\nstderr:\n%s" % (code, expected_exit, out, err))
    for needle in (read(prefix + ".expected_stderr", "") or "").splitlines():
        if needle.strip() and needle not in err:
            fail("stderr does not contain %r:\n%s" % (needle, err))
    if expected_exit == 2:
        if out:
            fail("a malformed script printed on stdout:\n" + out)
        name = "<stdin>" if use_stdin else script
        if not re.search(re.escape(name) + r":\d+:\d+: \S", err):
            fail("stderr lacks FILE:LINE:COLUMN: message:\n" + err)
        return
    expected = read(prefix + ".expected.jsonl")
    if expected is None:
        fail("missing " + prefix + ".expected.jsonl")
    compare_jsonl(out, expected)


def check_dot(tool, script, dot):
    code, out, err = run_tool([tool, "dot", script])
    if code != 0:
        fail("dot exited %d: %s" % (code, err))
    # Fig. 8 shape of the spray-painting scene: 5 bodies, 5 pose edges, 4 twist edges.
    clusters = len(re.findall(r"subgraph cluster_\d+ \{", out))
    dashed = len(re.findall(r"-> frame_\d+ \[style=dashed\]", out))
    solid = len(re.findall(r"frame_\d+ -> frame_\d+;", out))
    if (clusters, solid, dashed) != (5, 5, 4):
        fail("expected 5 clusters, 5 pose and 4 twist edges, got %d, %d, %d:\n%s"
             % (clusters, solid, dashed, out))
    if not dot:
        print("SKIP: graphviz `dot` not found")
        sys.exit(77)
    p = subprocess.run([dot, "-Tsvg"], input=out.encode(), capture_output=True, timeout=120)
    if p.returncode != 0 or b"<svg" not in p.stdout or p.stderr.strip():
        fail("dot -Tsvg failed (%d): %s" % (p.returncode, p.stderr.decode()))


def check_export(tool, script):
    code, out, err = run_tool([tool, "export", script])
    run_code, _, _ = run_tool([tool, "run", script])
    if code != run_code or code == 2:
        fail("export exited %d (run: %d): %s" % (code, run_code, err))
    if not out.startswith("# A scene written by semgraph") or "\nops:\n" not in out or "op: query" in out:
        fail("export printed no scene script:\n" + out)
    code, lines, err = run_tool([tool, "run", "-"], input_bytes=out.encode())
    if code != 0 or err or '"ok": false' in lines:
        fail("the exported script does not run cleanly (exit %d):\n%s%s\n%s" % (code, lines, err, out))
    code, again, err = run_tool([tool, "export", "-"], input_bytes=out.encode())
    if code != 0 or again != out:
        fail("the export of the exported script differs (exit %d):\n%s\n---\n%s" % (code, out, again))


def check_cli(tool):
    code, out, err = run_tool([tool, "--help"])
    if code != 0 or "Usage: semgraph run FILE" not in out or "angular_velocity" not in out:
        fail("--help: exit %d\n%s" % (code, out))
    # The example script in --help must itself run cleanly.
    example = out.split("\nScript:\n", 1)[1].split("\nOps and their fields:", 1)[0]
    code, ex_out, ex_err = run_tool([tool, "run", "-"], input_bytes=example.encode())
    if code != 0 or len(ex_out.splitlines()) != example.count("- {op:"):
        fail("the --help example: exit %d\n%s%s" % (code, ex_out, ex_err))
    for word in ("spec/", "shared/", "developers' guide"):
        if word in out:
            fail("--help refers outside the repository (%r)" % word)
    # --version: the project version of the top-level CMakeLists.txt.
    cmake = read(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "CMakeLists.txt"))
    version = re.search(r"project\(semgraph VERSION ([0-9.]+)", cmake).group(1)
    code, out, err = run_tool([tool, "--version"])
    if code != 0 or out != "semgraph %s\n" % version:
        fail("--version: exit %d, %r (expected semgraph %s)" % (code, out, version))
    # Subcommand help, not a file named --help.
    for command, needle in (("run", "print one JSON object per op"), ("dot", "Graphviz DOT"),
                            ("export", "scene script that rebuilds")):
        for flag in ("--help", "-h"):
            code, out, err = run_tool([tool, command, flag])
            if code != 0 or not out.startswith("Usage: semgraph %s FILE\n" % command) or \
                    needle not in out or "Exit status:" not in out or err:
                fail("%s %s: exit %d, stdout %r, stderr %r" % (command, flag, code, out[:300], err))
    for args in ([], ["run"], ["frobnicate", "x.yaml"], ["run", "a.yaml", "b.yaml"]):
        code, out, err = run_tool([tool] + args)
        if code != 2 or out or "Usage:" not in err:
            fail("%s: exit %d, stdout %r, stderr %r" % (args, code, out, err))
    # Hostile input: rejected as malformed (exit 2, located), never a crash or a hang.
    hostile = [
        (b"ops: " + b"[" * 200000 + b"]" * 200000, "<stdin>:1:69: the document is nested more"),
        (b"ops: " + b"{a: " * 100000, "nested more than 64 levels deep"),
        (b"ops:\n" + b"".join(b" " * (2 * i) + b"-\n" for i in range(1, 2000)), "<stdin>:65:"),
        (b"ops: []\n#" + b"x" * (16 << 20), "<stdin>:1:1: the script is larger than 16 MiB"),
    ]
    for text, needle in hostile:
        code, out, err = run_tool([tool, "run", "-"], input_bytes=text)
        if code != 2 or out or needle not in err:
            fail("hostile input %r...: exit %d, stdout %r, stderr %r" % (text[:20], code, out[:200], err))
    # Not UTF-8: refused with the position of the first bad byte and a message that says so;
    # a leading NUL (UTF-16 big-endian) must not make the reader decode UTF-16.
    encodings = [
        (b"ops: [{op: body, name: caf\xe9}]", "<stdin>:1:27: byte 0xE9 is not valid UTF-8; the script must be UTF-8"),
        ("ops: []".encode("utf-16-be"), "<stdin>:1:1: a raw NUL byte; the script must be UTF-8 text (NUL bytes at the start"),
        ("ops: []".encode("utf-16"), "<stdin>:1:1: the text starts with a UTF-16 byte-order mark; the script must be UTF-8"),
        (b"ops: [{op: body, name: a\x00b}]", "<stdin>:1:25: a raw NUL byte; the script must be UTF-8 text."),
    ]
    for text, needle in encodings:
        code, out, err = run_tool([tool, "run", "-"], input_bytes=text)
        if code != 2 or out or needle not in err:
            fail("encoding %r: exit %d, stdout %r, stderr %r" % (text[:20], code, out[:200], err))
    check_alias_bomb(tool)
    check_output_failures(tool)
    check_out_of_memory(tool)
    missing = "/nonexistent/semgraph/script.yaml"
    code, out, err = run_tool([tool, "run", missing])
    if code != 2 or out or missing + ": cannot read" not in err:
        fail("missing file: exit %d, stdout %r, stderr %r" % (code, out, err))


def check_alias_bomb(tool):
    """A 1 MiB name anchored once and aliased 500 times would expand to 500 MiB (and, before the
    limit, took 524 MB of memory and printed 525 MB). Expanded size, in units of one a node plus
    its text: root map 1, "ops" 4, list 1; the anchored op: map 1, "op" 3, "body" 5, "name" 5,
    the name 1 + 2^20, together A = 2^20 + 15. After k aliases the total is 2^20 + 21 + k A,
    at most 32 MiB = 2^25 for k <= 30: the 31st alias crosses. Line 1: 26 bytes before the
    name, the name, '}' at 2^20 + 27, then ", *o" per alias: the k-th '*' at 2^20 + 30 + 4 (k - 1)."""
    import resource
    text = b"ops: [&o {op: body, name: " + b"x" * (1 << 20) + b"}" + b", *o" * 500 + b"]\n"
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    code, out, err = run_tool([tool, "run", "-"], input_bytes=text)
    column = (1 << 20) + 30 + 4 * 30
    needle = "<stdin>:1:%d: the document is too large with its aliases expanded" % column
    if code != 2 or out or needle not in err:
        fail("alias bomb: exit %d, stdout %r, stderr %r (expected %r)" % (code, out[:200], err[:300], needle))
    peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    if peak_kib > max(before, 64 * 1024):
        fail("alias bomb: the tool peaked at %d KiB (more than 64 MiB)" % peak_kib)
    # Within the limit, aliases work as copies: 30 aliases of a 1 MiB name are 31 ops.
    ok_text = b"ops: [&o {op: body, name: " + b"x" * (1 << 20) + b"}" + b", *o" * 30 + b"]\n"
    code, out, err = run_tool([tool, "run", "-"], input_bytes=ok_text)
    lines = out.splitlines()
    if code != 1 or len(lines) != 31 or "(1048576 bytes)" not in lines[30] or len(out) > 31 * 400:
        fail("30 aliases: exit %d, %d lines, %d bytes, stderr %r" % (code, len(lines), len(out), err[:300]))


def check_output_failures(tool):
    """A failed write of the output exits 3 with a message on stderr."""
    script = b"ops: [" + b"{op: body, name: b%d}, " * 1 % 0 + b"".join(b"{op: body, name: b%d}, " % i for i in range(1, 2000)) + b"]"
    if os.path.exists("/dev/full"):
        with open("/dev/full", "wb") as full:
            p = subprocess.run([tool, "run", "-"], input=script, stdout=full, stderr=subprocess.PIPE, timeout=120)
        err = p.stderr.decode("utf-8", "replace")
        if p.returncode != 3 or "semgraph: cannot write the output: No space left on device" not in err:
            fail("> /dev/full: exit %d, stderr %r" % (p.returncode, err))
    # stdout closed (`semgraph run - >&-`).
    p = subprocess.run("exec %s run - >&-" % tool, shell=True, input=script, stderr=subprocess.PIPE, timeout=120)
    err = p.stderr.decode("utf-8", "replace")
    if p.returncode != 3 or "semgraph: cannot write the output: Bad file descriptor" not in err:
        fail("stdout closed: exit %d, stderr %r" % (p.returncode, err))


def check_out_of_memory(tool):
    """Running out of memory is exit 2 with a message naming the file, never an abort."""
    import resource
    with open(tool, "rb") as f:
        binary = f.read()
    if b"__asan_init" in binary or b"__tsan_init" in binary:
        # A sanitizer reserves terabytes of shadow memory: an address-space limit stops it
        # before main(). The check runs in the plain builds.
        print("out-of-memory check skipped: the tool is built with a sanitizer")
        return
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (96 << 20, 96 << 20))
    # 14 MiB of poses between fresh frames: each op adds two frames and a body to the graph.
    ops = b"".join(b"- {op: pose, of: f%d, body: B%d, wrt: w}\n" % (i, i) for i in range(300000))
    p = subprocess.run([tool, "run", "-"], input=b"ops:\n" + ops, capture_output=True, timeout=300,
                       preexec_fn=limit)
    err = p.stderr.decode("utf-8", "replace")
    if p.returncode != 2 or not re.search(r"^<stdin>(:\d+)?: out of memory while (reading the script|applying op \d+)", err, re.M):
        fail("out of memory: exit %d, stderr %r, %d bytes of stdout" % (p.returncode, err[-500:], len(p.stdout)))


def main(argv):
    mode = argv[1]
    if mode in ("run", "stdin"):
        check_script(argv[2], argv[3], argv[4], mode == "stdin")
    elif mode == "dot":
        check_dot(argv[2], argv[3], argv[4] if len(argv) > 4 else "")
    elif mode == "export":
        check_export(argv[2], argv[3])
    elif mode == "cli":
        check_cli(argv[2])
    else:
        fail("unknown mode " + mode)
    print("PASS")


if __name__ == "__main__":
    main(sys.argv)
