#!/usr/bin/env python3
"""Run the bad-input cases of cases.txt (the format is described there).

Bad input must end with one line "signorini: error: ..." naming the culprit
and a non-zero exit code, never an abort, a segfault or a backtrace; valid
input exits 0 with nothing on stderr.

Usage: run.py SIGNORINI_EXECUTABLE SOURCE_DIR [NAME_REGEX]

NAME_REGEX (Python syntax) runs only the cases whose name it matches (setup
lines all run, references too): e.g. run.py build/signorini . 'msh|mesh'.
"""

import os
import re
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
# what no output may contain (Open MPI's abort note too under mpirun)
CRASH = "stacktrace|aborted|segmentation"
MPI_CRASH = "MPI_ABORT|" + CRASH
# the command line's usage, ending its error messages
USAGE = ("; usage: signorini \\[--validate\\] FILE.prm | "
         "--print-parameters | --help$")
QUIET = "subsection Output\\n  set Print timing = false\\nend"


def grep(pattern, text, flags=()):
    """grep's basic regular expressions, as the messages were written for."""
    return subprocess.run(["grep", "-q", *flags, "--", pattern],
                          input=text, text=True).returncode == 0


def count_lines(pattern, text):
    return sum(1 for line in text.splitlines() if grep(pattern, line))


class Runner:
    def __init__(self, exe, src, work):
        self.exe = os.path.abspath(exe)
        self.src = os.path.abspath(src)
        self.work = work
        tests = os.path.join(self.src, "tests")
        # placeholders: file names (absolute, the cases name files from
        # parameter files in other directories) and text macros
        self.names = {
            "exe": self.exe, "src": self.src, "work": work,
            "tests": tests, "inputs": os.path.join(HERE, "inputs"),
            "block": os.path.join(tests, "inputs", "block.prm"),
            "msh22": os.path.join(tests, "meshes", "square-22.msh"),
            "msh41": os.path.join(tests, "meshes", "square-41.msh"),
            "cube": os.path.join(tests, "meshes", "cube.msh"),
            "usage": USAGE, "quiet": QUIET,
        }
        self.features = {
            "mpirun": shutil.which("mpirun") is not None,
            "user": os.geteuid() != 0,
            "mknod": self.can_mknod(),
        }
        self.eps = {}
        self.count = 0
        self.failures = 0

    def can_mknod(self):
        node = os.path.join(self.work, ".mknod")
        try:
            os.mknod(node, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
            os.remove(node)
            return True
        except OSError:
            return False

    def expand(self, text):
        # macros first: they hold placeholders themselves
        for key in ("quiet", "usage"):
            text = text.replace("{" + key + "}", self.names[key])
        for key, value in self.names.items():
            text = text.replace("{" + key + "}", value)
        return text

    def base(self, text):
        return self.expand(text).replace("\\n", "\n")

    def write(self, name, content):
        path = os.path.join(self.work, name)
        with open(path, "w") as f:
            f.write(content)
        return path

    @staticmethod
    def read(path):
        with open(path) as f:
            return f.read()

    # --- inputs ---

    def make_input(self, kind, value):
        """The command line arguments of an input KIND VALUE."""
        out = "set Output directory = %s/out\n" % self.work
        if kind == "args":
            return shlex.split(self.expand(value))
        if kind == "prm":
            return [self.write("case.prm", self.read(self.names["block"]) +
                               self.base(value) + "\n" + out)]
        if kind == "run":
            once = ("set Number of cycles = 1\n" + out +
                    "subsection Output\n  set Write vtu = false\nend\n")
            return [self.write("case.prm", self.read(self.names["block"]) +
                               once + self.base(value) + "\n")]
        if kind == "base":
            file, _, text = value.partition(" ")
            return [self.write("case.prm", self.read(self.expand(file)) +
                               self.base(text) + "\n" + out)]
        if kind == "mesh":
            mesh = ("subsection Mesh\n  set Source    = file\n"
                    "  set File name = %s\nend\n" % self.expand(value))
            return [self.write("case.prm", self.read(self.names["block"]) +
                               mesh + out)]
        if kind == "outdir":
            directory, _, text = value.partition(" ")
            return [self.write("case.prm", self.read(self.names["block"]) +
                               self.base(text) + "\n" +
                               "set Output directory = %s\n" %
                               self.expand(directory))]
        if kind == "hertz":
            return [self.write("hertz.prm", self.hertz_prm(
                *self.expand(value).split(" ")))]
        if kind == "cube":
            file, _, text = value.partition(" ")
            return [self.write("cube.prm",
                               self.cube_prm(self.expand(file)) +
                               self.base(text) + "\n")]
        raise ValueError("unknown input kind <%s>" % kind)

    def cube_prm(self, mesh):
        """A 3D case on MESH clamped on 1, loaded on 3, contact on 2."""
        return (
            "set Dimension = 3\nset Output directory = %s/out\n" % self.work +
            "subsection Mesh\n  set Source = file\n"
            "  set File name = %s\nend\n" % mesh +
            "subsection Boundary conditions\n  subsection Dirichlet 1\n"
            "    set Boundary ids = 1\n"
            "    set Function expression = 0; 0; 0\n  end\n"
            "  subsection Traction 1\n    set Boundary ids = 3\n"
            "    set Function expression = 0; 0; -0.01\n  end\nend\n"
            "subsection Contact\n  set Boundary ids = 2\n"
            "  set Direction = 0, 0, -1\n"
            "  subsection Gap\n    set Function expression = 0.001\n"
            "  end\nend\n"
            "subsection Error estimator\n  set Enable = false\nend\n")

    def hertz_prm(self, geometry, mesh=None):
        """The adaptive Hertz test remeshing GEOMETRY, from MESH (its
        coarse mesh by default)."""
        mesh = mesh or os.path.join(self.names["tests"], "meshes",
                                    "hertz-coarse.msh")
        text = self.read(os.path.join(self.names["tests"], "runs",
                                      "hertz_adaptive.prm"))
        for entry, value in (("File name", mesh),
                             ("Geometry file", geometry),
                             ("Output directory", self.work + "/out")):
            text = re.sub("set %s *=.*" % entry,
                          lambda m: "set %s = %s" % (entry, value), text)
        return text

    # --- one case ---

    def parse_input(self, text):
        """[needs:FEATURE]... [mpirun N | mpirun-abort N] [--validate]
        KIND VALUE"""
        needs, launcher, options = [], None, []
        words = text.split(" ")
        while words[0].startswith("needs:"):
            needs.append(words.pop(0)[len("needs:"):])
        if words[0] in ("mpirun", "mpirun-abort"):
            launcher = (words[0], words[1])
            needs.append("mpirun")
            words = words[2:]
        kind = words.pop(0)
        while kind == "--validate":
            options.append(kind)
            kind = words.pop(0)
        return needs, launcher, options, kind, " ".join(words)

    def run_case(self, name, text, exit_code, expected):
        needs, launcher, options, kind, value = self.parse_input(text)
        missing = [f for f in needs if not self.features[f]]
        if missing:
            print("ok   (skipped: no %s) %s" % (", ".join(missing), name))
            return
        reference = exit_code == "ref"
        if not reference:
            self.count += 1
        expected = self.expand(expected)
        out_dir = os.path.join(self.work, "out")
        if kind == "run" or reference or expected.startswith("eps "):
            shutil.rmtree(out_dir, ignore_errors=True)
        if kind == "shell":
            command = ["bash", "-c", self.expand(value)]
        else:
            command = [self.exe] + options + self.make_input(kind, value)
        if launcher:
            command = (["mpirun"] + (["-q"] if launcher[0] == "mpirun"
                                     else []) +
                       ["--oversubscribe", "-np", launcher[1]] + command)
        result = subprocess.run(command, cwd=self.work, capture_output=True,
                                text=True, errors="replace")
        self.write("stdout", result.stdout)
        self.write("stderr", result.stderr)
        # (a reference is a valid run whose eps is kept)
        problem = self.judge(result, "0" if reference else exit_code,
                             expected, launcher)
        if reference:
            if problem:
                print("FAIL reference %s: %s" % (name, problem))
                self.failures += 1
            else:
                self.eps[name] = self.statistic("eps")
            return
        if problem:
            print("FAIL %s (exit %d, expected %s): %s" %
                  (name, result.returncode, exit_code, problem))
            sys.stdout.write(result.stderr[:2000])
            self.failures += 1
        else:
            print("ok   %s%s" % (name, self.summary(result, expected)))

    def statistic(self, column):
        """COLUMN in the first row of the last run's statistics.csv."""
        try:
            with open(os.path.join(self.work, "out", "statistics.csv")) as f:
                header = f.readline().strip().split(",")
                row = f.readline().strip().split(",")
            return row[header.index(column)]
        except (OSError, ValueError, IndexError):
            return ""

    def judge(self, result, exit_code, expected, launcher):
        """What is wrong with RESULT (None if nothing)."""
        code, err, out = result.returncode, result.stderr, result.stdout
        if code != int(exit_code):
            return "exit code"
        if launcher and launcher[0] == "mpirun-abort":
            # Open MPI adds its own notes on the aborted job
            if count_lines("signorini: error: ", err) != 1 or not grep(
                    "^signorini: error: " + expected, err):
                return "not one error line <%s>" % expected
            return None
        crash = MPI_CRASH if launcher else CRASH
        if grep(crash, err + out, ["-i", "-E"]):
            return "crash on the output"
        if code != 0:
            if len(err.splitlines()) != 1 or not grep(
                    "^signorini: error: .*" + expected, err):
                return "not one error line <%s>" % expected
            return None
        if err:
            return "stderr not empty"
        if expected.startswith("Warning: "):
            if count_lines("^Warning: .*" + expected[len("Warning: "):],
                           out) != 1:
                return "no single warning line with <%s>" % expected
        elif expected.startswith("eps = 0: "):
            eps = self.statistic("eps")
            if (self.statistic("converged") != "1" or not eps or
                    float(eps) != 0 or
                    not grep(expected[len("eps = 0: "):], out)):
                return "eps <%s>, not exact" % eps
        elif expected.startswith("eps "):
            # eps = REFERENCE or eps ~TOLERANCE REFERENCE
            eps = self.statistic("eps")
            if expected.startswith("eps = "):
                ref, tolerance = expected[len("eps = "):], None
            else:
                tolerance, _, ref = expected[len("eps ~"):].partition(" ")
            want = self.eps.get(ref, "")
            if not eps or not want:
                return "eps <%s>, the reference %s <%s>" % (eps, ref, want)
            if tolerance is None and eps != want:
                return "eps = %s, %s gives %s" % (eps, ref, want)
            if tolerance is not None and (abs(float(eps) - float(want)) >
                                          float(tolerance) * float(want)):
                return "eps = %s, %s gives %s" % (eps, ref, want)
        elif expected:
            raise ValueError("unknown check <%s>" % expected)
        return None

    def summary(self, result, expected):
        if result.returncode != 0:
            lines = [line for line in result.stderr.splitlines()
                     if "signorini: error: " in line]
            return ": " + (lines[0] if lines else "")
        if expected.startswith("Warning: "):
            return ": " + " ".join(line for line in
                                   result.stdout.splitlines()
                                   if line.startswith("Warning: "))
        if expected.startswith("eps"):
            return ": eps = " + self.statistic("eps")
        valid = [line for line in result.stdout.splitlines()
                 if line.endswith(": valid")]
        return ": " + (valid[0] if valid else "exit 0")

    def setup(self, line):
        """$ [needs:FEATURE]... COMMAND: a shell command making inputs"""
        words = line.split(" ")
        if any(w.startswith("needs:") and not self.features[w[6:]]
               for w in words if w.startswith("needs:")):
            return
        command = " ".join(w for w in words if not w.startswith("needs:"))
        result = subprocess.run(["bash", "-c", self.expand(command)],
                                cwd=self.work)
        if result.returncode != 0:
            print("FAIL setup: %s" % command)
            self.failures += 1


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    selection = re.compile(sys.argv[3]) if len(sys.argv) == 4 else None
    work = tempfile.mkdtemp()
    os.environ["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    os.environ["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    # Open MPI's session directories in a tree of our own: in the shared
    # /tmp/ompi.HOST.UID another test's job, ending, removed the tree while
    # a run of ours created its directory there (orte_init failed, once)
    mpi_sessions = tempfile.mkdtemp()
    os.environ["OMPI_MCA_orte_tmpdir_base"] = mpi_sessions
    try:
        runner = Runner(sys.argv[1], sys.argv[2], work)
        with open(os.path.join(HERE, "cases.txt")) as f:
            for number, line in enumerate(f, 1):
                line = line.rstrip("\n")
                if line.endswith(" |"):
                    line += " "
                if not line.strip() or line.startswith("#"):
                    continue
                if line.startswith("$ "):
                    runner.setup(line[2:])
                    continue
                # name | input | exit | message: the name and the message
                # hold no " | ", the input may
                head, exit_code, expected = line.rsplit(" | ", 2)
                name, text = head.split(" | ", 1)
                if selection and exit_code != "ref" and \
                        not selection.search(name):
                    continue
                try:
                    runner.run_case(name.strip(), text.strip(),
                                    exit_code.strip(), expected.strip())
                except (ValueError, IndexError) as e:
                    print("FAIL cases.txt line %d: %s" % (number, e))
                    runner.failures += 1
        print("%d passed, %d failed" %
              (runner.count - runner.failures, runner.failures))
        sys.exit(runner.failures != 0)
    finally:
        shutil.rmtree(work, ignore_errors=True)
        shutil.rmtree(mpi_sessions, ignore_errors=True)


if __name__ == "__main__":
    main()
