"""Work beside the build (issue 46): ``workers.Beside`` runs a step in a forked process while the
build goes on — the same value as in this process, its errors raised here, and the work done here
where no fork is safe or the forked process dies."""

import os
import threading
import time

import pytest

from transplanter.core.errors import GeometryError
from transplanter.families.builder.workers import Beside

FORKS = hasattr(os, "fork")


def _alone() -> bool:
    return threading.active_count() == 1


def test_the_value_comes_back_from_the_fork_its_arguments_inherited_not_pickled():
    lock = threading.Lock()  # not picklable: the fork inherits it
    with Beside(lambda held, k: (os.getpid(), held.locked(), k * 2), lock, 21) as beside:
        pid, locked, value = beside.result()
    assert (locked, value) == (False, 42)
    if FORKS and _alone():
        assert pid != os.getpid()


def test_a_second_fork_runs_beside_the_first_and_an_unasked_one_is_stopped():
    """No pool and no thread here: the plots' fork starts while the STEP's still runs."""
    alone = _alone()  # (a pytest-xdist worker runs threads of its own: then the work is done here)
    with Beside(lambda: (time.sleep(0.3), os.getpid())[1]) as first:
        assert _alone() == alone
        with Beside(os.getpid) as second:
            pids = {first.result(), second.result()}
    if FORKS and alone:
        assert len(pids) == 2 and os.getpid() not in pids
    t = time.perf_counter()
    with Beside(time.sleep, 30):
        pass  # the caller went on without its value: the fork is killed, not waited for
    assert time.perf_counter() - t < 5 and _alone() == alone


def test_an_error_of_the_work_is_raised_here():
    def fails():
        raise GeometryError("the STEP solid fails its checks")

    with Beside(fails) as beside, pytest.raises(GeometryError, match="fails its checks"):
        beside.result()


def test_a_fork_that_dies_has_its_work_done_here():
    parent = os.getpid()
    with Beside(lambda: os._exit(3) if os.getpid() != parent else "done here") as beside:
        assert beside.result() == "done here"


def test_no_fork_while_other_threads_run():
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)
    other.start()
    try:
        with Beside(os.getpid) as beside:
            assert beside.result() == os.getpid()
    finally:
        stop.set()
        other.join()


def _in_a_daemon(conn) -> None:
    with Beside(os.getpid) as beside:
        conn.send((beside.result(), os.getpid()))


@pytest.mark.skipif(not FORKS, reason="needs fork")
def test_a_daemonic_process_does_the_work_itself():
    """A daemon may have no children (the design studio's slow judgement runs in one): the work is
    done in it, not refused."""
    import multiprocessing

    ctx = multiprocessing.get_context("fork")
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_in_a_daemon, args=(send,), daemon=True)
    child.start()
    try:
        assert receive.poll(60), "the daemon never answered (a pool it may not have, waited on)"
        ran_in, daemon = receive.recv()
    finally:
        child.kill()
        child.join()
    assert ran_in == daemon


FROZEN = """
import gc, json, os
from transplanter.families.builder import workers
from transplanter.families.builder.workers import Beside

def beside():
    with Beside(lambda: (os.getpid(), gc.get_freeze_count())) as b:
        during = gc.get_freeze_count()
        pid, seen = b.result()
    return {"forked": pid != os.getpid(), "during": during, "in_the_fork": seen, "after": gc.get_freeze_count()}

def in_worker():
    return {"inherited": gc.get_freeze_count(), **beside()}

out = {"before": gc.get_freeze_count(), "beside": beside()}
with workers.executor(1) as pool:
    out["pool"] = gc.get_freeze_count()
    out["worker"] = pool.submit(in_worker).result()
out["after_pool"] = gc.get_freeze_count()
print(json.dumps(out))
"""


@pytest.mark.skipif(not FORKS, reason="no fork on this platform")
def test_a_fork_runs_with_the_objects_frozen_and_they_are_thawed_when_it_ends():
    """Issue 46: the objects a fork inherits are in the collector's permanent generation while it
    runs (no collection walks them and copies their pages, in it or here), back in the collector
    once it has ended; a build worker, forked frozen, keeps its inherited objects frozen and never
    freezes its own for good (run in a process of its own: a pytest-xdist worker has threads, so
    its Beside does not fork)."""
    import json
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", FROZEN], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    top = out["beside"]
    assert out["before"] == 0 and top["forked"]
    assert top["during"] > 1000 and top["in_the_fork"] > 1000 and top["after"] == 0
    assert out["pool"] > 1000 and out["after_pool"] == 0
    worker = out["worker"]
    assert worker["forked"] and worker["inherited"] > 1000
    assert worker["during"] == worker["in_the_fork"] == worker["after"] == worker["inherited"]


INBOX = """
import json, os, threading
from transplanter.families.builder.workers import Beside

def work(k, receive):
    first, second = receive(), receive()
    return {"pid": os.getpid(), "got": [first(k) if callable(first) else first, second]}

out = {}
with Beside(work, 2, inbox=True) as b:  # values sent after the fork reach it, in order
    b.send("a")
    b.send("b")
    out["forked"] = b.result()
with Beside(work, 2, inbox=True) as b:  # a value that does not pickle: the work is done here
    b.send(lambda k: k * 21)
    b.send("unused")
    out["unpicklable"] = b.result()
stop = threading.Event()
t = threading.Thread(target=stop.wait)
t.start()
with Beside(work, 2, inbox=True) as b:  # no fork beside a thread: done here, receiving what was sent
    b.send("c")
    b.send("d")
    out["threads"] = b.result()
stop.set()
t.join()
try:
    Beside(os.getpid).send(1)
except TypeError as exc:
    out["no_inbox"] = str(exc)
out["me"] = os.getpid()
print(json.dumps(out))
"""


@pytest.mark.skipif(not FORKS, reason="no fork on this platform")
def test_a_fork_with_an_inbox_receives_what_is_sent_after_it_started():
    """Issue 46: a pair's plots are forked before the proof and sent the meshing plot once it is
    made — the values arrive in order; one that does not pickle, or no fork to be had, and the
    work is done here with the same values (run in a process of its own: see above)."""
    import json
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", INBOX], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    me = out["me"]
    assert out["forked"]["got"] == ["a", "b"] and out["forked"]["pid"] != me
    assert out["unpicklable"] == {"pid": me, "got": [42, "unused"]}
    assert out["threads"] == {"pid": me, "got": ["c", "d"]}
    assert "inbox=True" in out["no_inbox"]


#: what a task of the build's forks leaves in its process (a fresh fork must not see it)
_LEFT: list[int] = []


def _task(pause: float) -> tuple[int, int, float, float, int]:
    import gc

    seen = len(_LEFT)
    _LEFT.append(os.getpid())
    t0 = time.monotonic()
    time.sleep(pause)
    return os.getpid(), seen, t0, time.monotonic(), gc.get_freeze_count()


def _fails() -> None:
    raise GeometryError("the part's own error")


def _killed() -> None:
    import signal

    os.kill(os.getpid(), signal.SIGKILL)


@pytest.mark.skipif(not FORKS, reason="no fork on this platform")
def test_the_build_s_forks_run_each_task_in_a_fresh_process_at_most_jobs_at_once():
    """Issue 46: each part in a fresh fork of the builder as it was on entering (nothing a part left
    behind is under the next, nor the files the builder gathered since), at most ``jobs`` at once,
    the builder's objects frozen meanwhile; a part's error comes back as its error, a killed
    process as died, and leaving the block stops what still runs."""
    import gc

    from transplanter.families.builder.workers import Forks

    before = gc.get_freeze_count()
    with Forks(2) as pool:
        _LEFT.append(0)  # what this process gathers after entering (a part's files) is not in the forks
        tickets = [pool.submit(_task, 0.2) for _ in range(5)]
        done = dict(pool.next()[::2] for _ in tickets)
        assert len(pool) == 0
        rows = [done[t] for t in tickets]
        pids = {r[0] for r in rows}
        assert len(pids) == 5 and os.getpid() not in pids  # a process each
        assert all(r[1] == 0 for r in rows)  # none saw what another left behind, or this process since
        assert all(r[4] > 1000 for r in rows)  # this process's objects frozen in each
        spans = [(r[2], r[3]) for r in rows]
        at_once = max(sum(a <= t < b for a, b in spans) for t, _ in spans)
        assert at_once == 2

        failed = pool.submit(_fails)
        got, kind, value = pool.next()
        assert (got, kind) == (failed, "error") and isinstance(value, GeometryError) and "own error" in str(value)
        killed = pool.submit(_killed)
        got, kind, value = pool.next()
        assert (got, kind) == (killed, "died") and "without answering" in value

        slow, quick = pool.submit(_task, 30.0), pool.submit(_task, 0.0)
        t = time.monotonic()
        assert pool.next()[0] == quick
    assert time.monotonic() - t < 10.0 and len(pool) == 0  # the slow one stopped, not waited for
    assert gc.get_freeze_count() == before and _LEFT == [0]
    assert slow not in (quick, killed)


def _echo(data: bytes) -> bytes:
    return data[::-1]


@pytest.mark.skipif(not FORKS, reason="no fork on this platform")
def test_large_tasks_and_large_answers_pass_each_other():
    """A machine's task carries its gears' files (tens of MB) while another part's answer comes
    back: the builder handing out the one and the fork server passing on the other must not wait
    on each other (they did, through two pipes: the build hung)."""
    import signal

    from transplanter.families.builder.workers import Forks

    def late(*_):
        raise TimeoutError("the forks did not answer within 60 s")

    was = signal.signal(signal.SIGALRM, late)
    signal.alarm(60)
    try:
        payloads = [bytes([k]) * 3_000_000 + b"end" for k in range(6)]
        with Forks(2) as pool:
            tickets = {pool.submit(_echo, p): p for p in payloads}
            got = dict(pool.next()[::2] for _ in payloads)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, was)
    assert all(got[t] == p[::-1] for t, p in tickets.items())


def test_where_no_process_can_be_forked_the_build_s_tasks_are_done_here(monkeypatch):
    from transplanter.families.builder.workers import Forks

    def refused():
        raise OSError("Resource temporarily unavailable")

    monkeypatch.setattr(os, "fork", refused)
    with Forks(2) as pool:
        mine, failed = pool.submit(os.getpid), pool.submit(_fails)
        assert pool.next() == (mine, "value", os.getpid())
        got, kind, value = pool.next()
        assert (got, kind) == (failed, "error") and isinstance(value, GeometryError)
        assert len(pool) == 0


#: a process whose Beside waits on its inbox, killed before it sends anything (run in a process of
#: its own: the test workers' threads keep a fork from being made)
ORPHAN = """
import os, signal, sys, time
from transplanter.families.builder.workers import Beside
def wait(receive):
    return receive()
work = Beside(wait, inbox=True)
print(work._proc.pid if work._proc is not None else -1, flush=True)
os.kill(os.getpid(), signal.SIGKILL)
"""


def _ended(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/status") as f:
            return any(line.startswith("State:") and "Z" in line for line in f)  # a zombie: ended
    except FileNotFoundError:
        return True


def _ends(pid: int, within: float = 20.0) -> bool:
    """Whether process ``pid`` has ended or ends within ``within`` s."""
    deadline = time.monotonic() + within
    while not _ended(pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    return _ended(pid)


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="reads /proc")
def test_a_fork_waiting_on_its_inbox_ends_when_its_parent_is_killed():
    """A process stopped while its work beside it waits on its inbox (the build stopped: the fork
    server kills a part's process) leaves nothing waiting: the fork holds no writing end of its
    own inbox, so the inbox ends with the parent and so does the fork (it waited for ever)."""
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", ORPHAN], capture_output=True, text=True, timeout=120)
    pid = int(proc.stdout.split()[0])
    assert pid > 0, proc.stderr
    assert _ends(pid)
    assert "Traceback" not in proc.stderr


KILLED_BUILDER = """
import os, signal, sys, threading, time
from transplanter.families.builder.workers import Forks
pool = Forks(2).__enter__()
pool.submit(time.sleep, 60)
how = sys.argv[1]
if how == "SIGKILL mid-send":  # a task larger than the pipe, its sending cut: the server reads half a message
    pool.submit(len, bytes(64 << 20))
stop = {"SIGTERM": lambda: os.killpg(0, signal.SIGTERM), "SIGHUP": lambda: os.killpg(0, signal.SIGHUP)}
threading.Timer(0.3, stop.get(how, lambda: os.kill(os.getpid(), signal.SIGKILL))).start()
print(pool._dir, pool._server, flush=True)
pool.next()
pool.next()
"""


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="reads /proc")
@pytest.mark.parametrize("stop", ["SIGKILL", "SIGKILL mid-send", "SIGTERM", "SIGHUP"])
def test_a_killed_builder_leaves_no_fork_folder(tmp_path, stop):
    """A build killed — SIGKILL to it (also while it sends a large task), SIGTERM or SIGHUP to its
    whole process group as ``timeout`` and a closed terminal send them — never leaves its ``with``
    block: its fork server, seeing it gone, stops the part still running and removes the
    temporary folder the answers go through."""
    import subprocess
    import sys

    env = {**os.environ, "TMPDIR": str(tmp_path)}
    command = [sys.executable, "-c", KILLED_BUILDER, stop]
    with subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env, start_new_session=True, text=True
    ) as proc:
        folder, server = proc.stdout.readline().split()
        proc.stdout.close()
        proc.wait(timeout=60)
    assert folder.startswith(str(tmp_path))
    assert _ends(int(server))
    assert list(tmp_path.glob("transplanter-forks-*")) == []


DISPOSITION = """
import signal, sys
from transplanter.families.builder.workers import Forks
def handler(number, frame):
    pass
def disposition():
    found = signal.getsignal(signal.SIGTERM)
    return getattr(found, "__name__", None) or found.name  # a function, or SIG_DFL / SIG_IGN
if sys.argv[1] == "handler":
    signal.signal(signal.SIGTERM, handler)
with Forks(1) as pool:
    pool.submit(disposition)
    print(pool.next()[2])
"""


@pytest.mark.parametrize(("builder", "part"), [("default", "SIG_DFL"), ("handler", "handler")])
def test_a_part_takes_sigterm_as_the_builder_does(builder, part):
    """The fork server ignores SIGTERM (it outlives its group's); the parts it forks take it back as
    the builder had it."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", DISPOSITION, builder], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == part, out.stderr[-2000:]
