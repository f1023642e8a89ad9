"""The sandbox holds from the host's point of view, with the audit hook as shipped and off.

Every hostile skill here runs twice: as it is, and with the audit hook switched off
inside the child first (what a skill can do to Python code in its own process). Each time
the test checks on the host that nothing happened: no file written or changed outside the
sandbox, no host secret in anything the run reports, no connection to a host socket, no
host process signalled, no process of the sandbox left running. What the findings say is
not the proof; the host's state is.
"""

from __future__ import annotations

import ast
import json
import os
import socket
import subprocess
import sys
import textwrap
import time
import uuid
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from skillwright.interfaces.inventory import Inventory
from skillwright.runtime.isolation import layout
from skillwright.runtime.report import RunProgress, RunReport
from skillwright.runtime.run import run_skill
from skillwright.runtime.sandbox import ChildPool, ForkServer, SandboxProcess
from tests.conftest import REPO_ROOT
from tests.runtime.conftest import processes_with, quick

SKILL = """
import os
import signal
import socket
import sys

{preamble}
from pyskillup.decorators.decorators import *
from pyskillup.decorator_check.decorator_check import ROS2Skill
from pyskillup.decorators.skill_interface import SkillInterface


@skill(skill_interface=SkillInterface.REST, skill_iri="urn:a", module_iri="urn:b",
       capability_iri="urn:c", description="a hostile skill")
class Hostile(ROS2Skill):
    def __init__(self) -> None:
        super().__init__("hostile")

    def say(self, text: object) -> None:
        self.node.get_logger().info(str(text))

    @execute
    def execute(self) -> None:
{attack}
"""

GUARD_OFF = """
_guard = sys.modules["_skillwright_child.guard"]
_guard._Guard.check = lambda self, event, args: None
"""
"""Switches the audit hook off: its object stays installed, its check does nothing."""

MODES = {"guard as shipped": "", "guard off": GUARD_OFF}


@dataclass
class Host:
    """What the host plants and watches."""

    folder: Path
    """A folder of the host's /tmp the skill is told about."""
    token: str
    secret: Path
    unix_path: Path
    abstract: str
    sleeper: subprocess.Popen[bytes]
    listener: socket.socket
    abstract_listener: socket.socket
    tcp: socket.socket

    def values(self) -> dict[str, str]:
        return {
            "tmp": str(self.folder),
            "token": self.token,
            "home": str(Path.home()),
            "repo": str(REPO_ROOT),
            "secret_path": str(self.secret),
            "unix_path": str(self.unix_path),
            "abstract": self.abstract,
            "sleeper": str(self.sleeper.pid),
            "port": str(self.tcp.getsockname()[1]),
        }

    def created(self) -> list[Path]:
        """Files with the token in their name anywhere the skill was pointed at."""
        places = [self.folder, Path.home(), REPO_ROOT, Path("/tmp")]
        found = [p for place in places for p in place.glob(f"*{self.token}*")]
        return [p for p in found if p != self.folder]

    def connections(self) -> list[str]:
        found = []
        for name, listener in (
            ("unix", self.listener),
            ("abstract", self.abstract_listener),
            ("tcp", self.tcp),
        ):
            try:
                connection, _ = listener.accept()
            except (BlockingIOError, TimeoutError):
                continue
            connection.close()
            found.append(name)
        return found


@pytest.fixture
def host(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Host]:
    token = uuid.uuid4().hex[:12]
    folder = Path("/tmp") / f"skillwright-host-{token}"
    folder.mkdir()
    secret = folder / "secret.txt"
    secret.write_text(f"SECRET-{token}\n", encoding="utf-8")
    secret.chmod(0o600)
    unix_path = folder / "listener.sock"
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(str(unix_path))
    unix_path.chmod(0o777)
    abstract = f"skillwright-test-{token}"
    abstract_listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    abstract_listener.bind("\0" + abstract)
    tcp = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    tcp.bind(("127.0.0.1", 0))
    for sock in (listener, abstract_listener, tcp):
        sock.listen(4)
        sock.setblocking(False)
    sleeper = subprocess.Popen(["sleep", "600"], start_new_session=True)
    try:
        yield Host(
            folder, token, secret, unix_path, abstract, sleeper, listener, abstract_listener, tcp
        )
    finally:
        sleeper.kill()
        sleeper.wait()
        for sock in (listener, abstract_listener, tcp):
            sock.close()
        for path in sorted(folder.rglob("*"), reverse=True):
            path.unlink() if not path.is_dir() else path.rmdir()
        folder.rmdir()


def hostile(attack: str, preamble: str = "", **values: str) -> str:
    body = textwrap.indent(textwrap.dedent(attack).strip("\n"), " " * 8)
    return SKILL.format(preamble=preamble, attack=body.format(**values))


def _host_secrets() -> list[str]:
    """Text of the host's that must never reach a run's report."""
    secrets = []
    for path in (Path("/etc/shadow"), Path("/etc/hostname")):
        try:
            first = path.read_text(encoding="utf-8").splitlines()[0].strip()
        except (OSError, IndexError, UnicodeDecodeError):
            continue
        if len(first) > 4:
            secrets.append(first)
    return secrets


def _root_entries() -> list[str]:
    """Names in /root other than those on the way to the files the sandbox holds."""
    root = layout()
    shown = {
        Path(p).relative_to("/root").parts[0]
        for p in (*root.folders, *root.files)
        if p.startswith("/root/")
    }
    try:
        names = {p.name for p in Path("/root").iterdir()}
    except OSError:
        return []
    return sorted(names - shown)


ATTACKS: dict[str, str] = {
    "write host /tmp": 'open("{tmp}/written-{token}", "w").write("x")',
    "write $HOME": 'open("{home}/pwned-{token}", "w").write("x")',
    "write the repository": 'open("{repo}/pwned-{token}", "w").write("x")',
    "read /etc/shadow": 'self.say(open("/etc/shadow").read())',
    "read a planted host file": 'self.say(open("{secret_path}").read())',
    "list /root": 'self.say(os.listdir("/root"))',
    "connect to a host unix socket": """
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.connect("{unix_path}")
        s.sendall(b"{token}")
    """,
    "connect to a host abstract socket": """
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.connect("\\0{abstract}")
        s.sendall(b"{token}")
    """,
    "connect to host loopback": """
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.connect(("127.0.0.1", {port}))
    """,
    "os.system": 'os.system("touch {tmp}/system-{token}")',
    "subprocess": """
        import subprocess
        subprocess.run(["/bin/sh", "-c", "touch {tmp}/subprocess-{token}"])
    """,
    "os.execv a shell": 'os.execv("/bin/sh", ["sh", "-c", "touch {tmp}/exec-{token}"])',
    "os.execv the interpreter": """
        os.execv(sys.executable, [sys.executable, "-c", "open('{tmp}/exec-{token}', 'w')"])
    """,
    "/proc/1/root": """
        self.say(os.listdir("/proc/1/root/"))
        open("/proc/1/root{tmp}/proc-{token}", "w").write("x")
    """,
    "/proc/self/fd": """
        for fd in range(64):
            try:
                target = os.readlink(f"/proc/self/fd/{{fd}}")
            except OSError:
                continue
            self.say(target)
            try:
                folder = os.path.dirname(os.path.dirname(target))
                open(os.path.join(folder, "fd-{token}"), "w").write("x")
            except OSError:
                pass
        open("/proc/self/cwd/../../tmp/fd-{token}", "w").write("x")
    """,
    "symlink out of the scratch folder": """
        os.symlink("{tmp}/link-{token}", "escape")
        open("escape", "w").write("x")
    """,
    "hard link to a host file": """
        os.link("{secret_path}", "hard")
        self.say(open("hard").read())
    """,
    "os.kill(0)": "os.kill(0, signal.SIGKILL)",
    "os.kill(-1)": "os.kill(-1, signal.SIGKILL)",
    "os.kill a host pid and the sandbox's": """
        for pid in [{sleeper}, *range(1, 64)]:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        open("{tmp}/survived-{token}", "w").write("x")
    """,
    "fork bomb": """
        while True:
            os.fork()
    """,
    "ctypes": """
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        self.say(libc.unshare(0x10000000 | 0x00020000))
        self.say(libc.mount(b"none", b"/tmp", b"tmpfs", 0, None))
        fd = libc.open(b"{tmp}/ctypes-{token}", 0o101, 0o644)
        self.say(fd)
    """,
    "ctypes through numpy": """
        import numpy
        ctypes = numpy.ctypeslib.ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        fd = libc.open(b"{tmp}/numpy-ctypes-{token}", 0o101, 0o644)
        self.say(fd)
    """,
    "guard through gc": """
        import gc
        for thing in gc.get_objects():
            if type(thing).__name__ == "_Guard":
                type(thing).check = lambda self, event, args: None
        open("{tmp}/gc-{token}", "w").write("x")
    """,
    "guard through __subclasses__": """
        for kind in object.__subclasses__():
            if kind.__name__ == "_Guard":
                kind.check = lambda self, event, args: None
        open("{tmp}/subclasses-{token}", "w").write("x")
    """,
    "guard through frames": """
        frame = sys._getframe()
        while frame is not None:
            for value in (*frame.f_locals.values(), *frame.f_globals.values()):
                kind = getattr(value, "_Guard", None)
                if isinstance(kind, type):
                    kind.check = lambda self, event, args: None
            frame = frame.f_back
        open("{tmp}/frames-{token}", "w").write("x")
    """,
}


def _contained(report: RunReport, host: Host, *, pool_closed: bool = True) -> None:
    """The host's state after the run: the whole proof of containment. With a pool still
    open, its fork server (and a spare child) still run, rightly."""
    # The attack itself ran: a broken attack would prove nothing.
    assert not any(f.check == "run.syntax" or "NameError" in f.message for f in report.findings), (
        report.findings
    )
    episode = report.trace.episodes[0]
    if pool_closed:
        assert processes_with(episode.isolation["sandbox"]) == [], "a sandboxed process survived"
    assert not Path(episode.isolation["folder"]).exists()
    assert host.created() == [], "the skill wrote on the host"
    assert host.secret.read_text(encoding="utf-8") == f"SECRET-{host.token}\n"
    assert host.connections() == [], "the skill reached a host socket"
    assert host.sleeper.poll() is None, "the skill killed a host process"
    text = report.model_dump_json()
    assert f"SECRET-{host.token}" not in text
    for secret in _host_secrets():
        assert secret not in text
    for name in _root_entries():
        assert f"'{name}'" not in text, f"the skill listed /root/{name}"


@pytest.mark.parametrize("mode", MODES, ids=list(MODES))
@pytest.mark.parametrize("attack", ATTACKS, ids=list(ATTACKS))
def test_the_host_is_untouched(
    attack: str, mode: str, host: Host, mr1_inventory: Inventory
) -> None:
    source = hostile(ATTACKS[attack], MODES[mode], **host.values())

    report = run_skill(Path("hostile.py"), mr1_inventory, source=source, scenario=quick())

    assert report.trace.episodes, report.findings
    _contained(report, host)


def test_switching_the_guard_off_works(mr1_inventory: Inventory) -> None:
    # The proof above means something only if the skill really gets past the audit hook:
    # importing ctypes is refused by the hook, and the kernel has no reason to.
    attack = """
        import ctypes
        self.say(ctypes.sizeof(ctypes.c_int))
    """
    shipped = run_skill(Path("s.py"), mr1_inventory, source=hostile(attack), scenario=quick())
    off = run_skill(
        Path("s.py"), mr1_inventory, source=hostile(attack, GUARD_OFF), scenario=quick()
    )

    assert any(f.check == "run.sandbox" for f in shipped.findings), shipped.findings
    assert off.findings == []
    assert [e["text"] for e in off.trace.episodes[0].events if e["kind"] == "log"] == ["4"]


def test_the_sandbox_root_holds_only_what_a_skill_needs(
    mr1_inventory: Inventory, monkeypatch: pytest.MonkeyPatch
) -> None:
    children: list[SandboxProcess] = []
    real_fork = ForkServer.fork

    def fork(server: ForkServer) -> SandboxProcess:
        children.append(real_fork(server))
        return children[-1]

    seen: dict[str, str] = {}

    def on_progress(progress: RunProgress) -> None:
        # The child is alive in its execute state: look at it from the host.
        if progress.event == "state-start" and progress.state == "execute":
            pid = children[-1].pid
            seen["status"] = Path(f"/proc/{pid}/status").read_text()
            root = Path(f"/proc/{pid}/root")
            seen["root"] = repr(sorted(p.name for p in root.iterdir()))
            seen["etc"] = repr(sorted(p.name for p in (root / "etc").iterdir()))
            seen["tmp"] = repr(sorted(p.name for p in (root / "tmp").iterdir()))
            for kind in ("net", "pid", "mnt", "user", "ipc", "uts"):
                seen[kind] = str(Path(f"/proc/{pid}/ns/{kind}").readlink())

    monkeypatch.setattr(ForkServer, "fork", fork)
    attack = """
        self.say((os.getuid(), os.getgid(), os.getgroups()))
        os.listdir("/")
    """
    report = run_skill(
        Path("s.py"),
        mr1_inventory,
        source=hostile(attack, GUARD_OFF),
        scenario=quick(),
        on_progress=on_progress,
    )

    logs = [e["text"] for e in report.trace.episodes[0].events if e["kind"] == "log"]
    [ids] = (ast.literal_eval(text) for text in logs)
    # What the sandbox's root holds, seen from the host: the folders of the layout and the
    # loader's links, nothing else of the host's.
    bound = {Path(p).parts[1] for p in (*layout().folders, *layout().files)}
    linked = {Path(link).parts[1] for link, _ in layout().links}
    assert set(ast.literal_eval(seen["root"])) == bound | linked | {"dev", "proc", "tmp"}
    assert ast.literal_eval(seen["etc"]) in (["ld.so.cache"], [])
    under_tmp = {
        Path(p).relative_to("/tmp").parts[0]
        for p in (*layout().folders, *layout().files)
        if p.startswith("/tmp/")
    }
    scratch = set(ast.literal_eval(seen["tmp"])) - under_tmp
    assert len(scratch) == 1, "only this child's scratch folder (and what is bound under /tmp)"
    # Landlock: the skill may not even list the root of its own sandbox.
    [denied] = report.findings
    assert "Permission denied: '/'" in denied.message
    status = dict(line.split(":\t", 1) for line in seen["status"].splitlines() if ":\t" in line)
    if os.getuid() == 0:
        assert ids == (65534, 65534, []), "started as root, the skill runs as nobody"
        assert status["Uid"].split() == ["65534"] * 4, "and is nobody on the host too"
    else:
        assert ids[0] == os.getuid()
    for capabilities in ("CapInh", "CapPrm", "CapEff", "CapBnd", "CapAmb"):
        assert int(status[capabilities], 16) == 0
    assert status["NoNewPrivs"] == "1"
    assert status["Seccomp"] == "2"
    assert int(status["Seccomp_filters"]) >= 3, "base, fallbacks and the child's own"
    for kind in ("net", "pid", "mnt", "user", "ipc", "uts"):
        assert seen[kind] != str(Path(f"/proc/self/ns/{kind}").readlink()), f"no {kind} namespace"
    episode = report.trace.episodes[0]
    assert episode.isolation["namespaces"] == "user, mount, pid, network, ipc, uts"
    assert episode.isolation["seccomp"] == "base, fallbacks, child"


def test_a_hostile_child_leaves_the_pool_and_its_fork_server_working(
    host: Host, mr1_inventory: Inventory
) -> None:
    attacks = ["os.kill a host pid and the sandbox's", "os.kill(-1)", "fork bomb"]
    with ChildPool() as children:
        for attack in attacks:
            source = hostile(ATTACKS[attack], GUARD_OFF, **host.values())
            report = run_skill(
                Path("hostile.py"),
                mr1_inventory,
                source=source,
                scenario=quick(),
                children=children,
            )
            _contained(report, host, pool_closed=False)
            server = children.server
            assert server is not None
            assert server.alive(), f"{attack} took down the fork server"
        calm = run_skill(
            Path("calm.py"), mr1_inventory, source=hostile("self.say('calm')"), children=children
        )
        marker = children.server.marker if children.server is not None else ""
    assert calm.passed, calm.findings
    assert processes_with(marker) == []


def test_a_run_without_isolation_says_so(mr1_inventory: Inventory) -> None:
    with ChildPool(isolated=False) as children:
        report = run_skill(
            Path("s.py"), mr1_inventory, source=hostile("self.say('x')"), children=children
        )
    assert report.passed, report.findings
    assert report.trace.episodes[0].isolation["namespaces"] == "none (--unsafe-no-isolation)"


def _unprivileged_command() -> list[str] | None:
    """A command that runs the rest of its arguments as ``nobody`` where this machine
    lets root arrange it (a private mount namespace in which the interpreter's folders
    can be reached by nobody), else ``None``."""
    if os.getuid() != 0 or not all(
        Path(p).exists() for p in ("/usr/bin/unshare", "/usr/bin/setpriv")
    ):
        return None
    needed = [Path(sys.base_prefix), REPO_ROOT]
    blocked = sorted(
        {
            parent
            for path in needed
            for parent in [path, *path.parents]
            if parent.is_dir() and not parent.stat().st_mode & 0o001
        }
    )
    if len(blocked) > 1:
        return None
    # Within the private mount namespace: keep the blocked folder's needed children, put a
    # world-traversable tmpfs over it and bind the children back.
    script = ["set -e", "mount --make-rprivate /"]
    for folder in blocked:
        keep = f"/tmp/.skillwright-keep-{uuid.uuid4().hex[:8]}"
        children = sorted(
            {path.relative_to(folder).parts[0] for path in needed if folder in path.parents}
        )
        script += [f"mkdir -p {keep}", f"mount --bind {folder} {keep}"]
        script += [f"mount -t tmpfs -o mode=0755 tmpfs {folder}"]
        for child in children:
            script += [
                f"mkdir -p {folder}/{child}",
                f"mount --bind {keep}/{child} {folder}/{child}",
            ]
    script.append('exec setpriv --reuid=65534 --regid=65534 --clear-groups "$@"')
    return ["unshare", "--mount", "sh", "-c", "\n".join(script), "sh"]


RUN_AS_USER = """
import json, sys
from pathlib import Path
from skillwright.interfaces.load import load_inventory
from skillwright.runtime.run import run_skill
from skillwright.runtime.scenario import Deadlines, RunScenario
inventory = load_inventory(Path(sys.argv[1]))
scenario = RunScenario(deadlines=Deadlines(state=10.0, busy=1.0, run=30.0), stop_run="never")
for source in json.loads(sys.stdin.read()):
    report = run_skill(Path("hostile.py"), inventory, source=source, scenario=scenario)
    print(report.model_dump_json())
"""


def test_the_sandbox_holds_for_an_unprivileged_user(host: Host, tmp_path: Path) -> None:
    prefix = _unprivileged_command()
    if prefix is None:
        pytest.skip("this machine gives no way to run the test as an unprivileged user")
    attacks = [
        "write host /tmp",
        "read a planted host file",
        "connect to a host unix socket",
        "os.system",
        "os.kill a host pid and the sandbox's",
        "fork bomb",
    ]
    sources = [hostile(ATTACKS[a], GUARD_OFF, **host.values()) for a in attacks]
    sources.append(hostile("self.say(os.getuid())", GUARD_OFF))
    home = tmp_path / "home"
    home.mkdir()
    tmp_path.chmod(0o755)
    home.chmod(0o777)
    environment = {
        "PATH": "/usr/bin:/bin",
        "HOME": str(home),
        "SKILLWRIGHT_CACHE_DIR": str(home / "cache"),
        "LANG": "C.UTF-8",
    }
    started = time.monotonic()
    result = subprocess.run(
        [
            *prefix,
            sys.executable,
            "-c",
            RUN_AS_USER,
            str(REPO_ROOT / "capabilities/recordings/mr1"),
        ],
        input=json.dumps(sources),
        capture_output=True,
        text=True,
        env=environment,
        cwd=str(home),
        timeout=300,
        check=False,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    reports = [RunReport.model_validate_json(line) for line in result.stdout.splitlines()]
    assert len(reports) == len(sources), time.monotonic() - started
    for report in reports[:-1]:
        _contained(report, host)
    logs = [e["text"] for e in reports[-1].trace.episodes[0].events if e["kind"] == "log"]
    assert logs, reports[-1].findings
    assert logs == ["65534"]
    assert reports[-1].trace.episodes[0].isolation["namespaces"].startswith("user, mount")
