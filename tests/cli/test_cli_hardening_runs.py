"""The command line under hostile input to runs and sweeps: every case one line and exit 2,
every wait bounded by its stated timeout (checked on the socket calls, not a wall clock),
never a traceback or a folder mixing two runs."""

import os
import socket
import struct
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from uma.cli import main

REPO = Path(__file__).resolve().parents[2]


class _Server:
    """A TCP server on 127.0.0.1 that greets each connection with `greeting`, then idles."""

    def __init__(self, greeting: bytes):
        self.greeting = greeting
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.open: list[socket.socket] = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            self.open.append(conn)
            if self.greeting:
                conn.sendall(self.greeting)

    def close(self):
        self.sock.close()
        for conn in self.open:
            conn.close()


def _bounded_waits(monkeypatch) -> dict[str, list]:
    """Record every wait the scheduler check asks of a socket: the connection's timeout and
    each `settimeout`, so a test proves every blocking call bounded without a wall clock."""
    import uma.experiments.scheduler as scheduler

    waits: dict[str, list] = {"connect": [], "settimeout": []}
    real_connect, real_settimeout = scheduler.socket.create_connection, socket.socket.settimeout

    def connect(address, timeout=None, *args, **kwargs):
        waits["connect"].append(timeout)
        return real_connect(address, timeout, *args, **kwargs)

    def settimeout(sock, value):
        waits["settimeout"].append(value)
        return real_settimeout(sock, value)

    monkeypatch.setattr(scheduler.socket, "create_connection", connect)
    monkeypatch.setattr(socket.socket, "settimeout", settimeout)
    return waits


@pytest.mark.parametrize(
    "greeting, said",
    [
        (b"HTTP/1.0 400 Bad Request\r\n\r\n", "does not speak Dask's protocol"),
        (struct.pack("Q", 3 * 2**60), "does not speak Dask's protocol"),  # "3 EiB follow"
        (struct.pack("Q", 40) + os.urandom(40), "does not speak Dask's protocol"),
        (b"", "no Dask scheduler answered at 'tcp://127.0.0.1:PORT' within 0.5 s"),
    ],
    ids=["http", "huge-length", "random", "silent"],
)
def test_a_scheduler_that_is_not_dask_is_one_line_within_the_timeout(
    folder, capsys, monkeypatch, greeting, said
):
    server = _Server(greeting)
    address = f"tcp://127.0.0.1:{server.port}"
    waits = _bounded_waits(monkeypatch)
    try:
        code = main(["sweep", str(folder / "exp.yaml"), "--scheduler", address, "--timeout", "0.5"])
    finally:
        server.close()
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("uma: error: --scheduler: "), err
    assert said.replace("PORT", str(server.port)) in err
    assert not (folder / "results").exists()
    # one connection, and every wait on it within what is left of the 0.5 s asked
    assert waits["connect"] == [0.5], waits
    assert waits["settimeout"] and all(0 < w <= 0.5 for w in waits["settimeout"]), waits


def test_a_closed_port_is_refused_at_once(folder, capsys, monkeypatch):
    with socket.create_server(("127.0.0.1", 0)) as probe:
        port = probe.getsockname()[1]  # free once closed
    waits = _bounded_waits(monkeypatch)
    code = main(["sweep", str(folder / "exp.yaml"), "--scheduler", f"tcp://127.0.0.1:{port}"])
    assert code == 2
    # tried once, no retry: the only timeout set is the connection's own
    assert len(waits["connect"]) == 1 and waits["settimeout"] == waits["connect"], waits
    err = capsys.readouterr().err
    assert err == (
        f"uma: error: --scheduler: cannot reach a Dask scheduler at 'tcp://127.0.0.1:{port}' "
        f"(Connection refused)\n"
    )


@pytest.mark.parametrize(
    "address",
    ["not-a-url", "tcp://", "tcp://host", "tcp://host:99999", "http://h:1", "tcp://h:1/x"],
)
def test_an_address_that_is_not_tcp_host_port_is_one_line(address):
    from uma.errors import ConfigError
    from uma.experiments.scheduler import parse_scheduler_address

    with pytest.raises(ConfigError, match=r"^--scheduler: expected tcp://HOST:PORT, got '"):
        parse_scheduler_address(address)


def test_not_a_url_ends_at_once_without_client_noise(folder):
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "uma",
            "sweep",
            str(folder / "exp.yaml"),
            "--scheduler",
            "not-a-url",
        ],
        env=dict(os.environ, PYTHONPATH=str(REPO)),
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert done.returncode == 2
    assert done.stderr == "uma: error: --scheduler: expected tcp://HOST:PORT, got 'not-a-url'\n"


# --- uma run: the folder is replaced whole, and only a results folder is replaced -------------


def test_run_refuses_an_out_folder_holding_other_files_before_simulating(folder, capsys):
    out = folder / "R"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    code = main(["run", str(folder / "base.yaml"), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "holds files that are not results (notes.txt)" in err
    assert [p.name for p in out.iterdir()] == ["notes.txt"]


def test_a_run_that_fails_writing_leaves_the_earlier_run_whole(folder, capsys, monkeypatch):
    import uma.atomic

    out = folder / "R"
    assert main(["run", str(folder / "base.yaml"), "--out", str(out), "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {"scenario.yaml", "metrics.json", "frames.csv", "events.csv"}

    def disk_full(folder):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(uma.atomic, "_fsync_tree", disk_full)
    code = main(["run", str(folder / "base.yaml"), "--out", str(out), "--quiet", "--seed", "7"])
    err = capsys.readouterr().err
    assert code == 2 and err == f"uma: error: {out}: cannot write (No space left on device)\n"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in folder.iterdir()) == ["R", "base.yaml", "exp.yaml"]
