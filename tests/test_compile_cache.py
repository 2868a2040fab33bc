"""The on-disk cache of compiled objects: `pressocp.jitcc` (the caching compiler) against a compiler
that logs its calls, and `pressocp.compile_cache.jit_options` through CasADi in two processes."""

import os
import stat
import subprocess
import sys
import textwrap

import pytest

from pressocp import compile_cache
from pressocp.jitcc import compile_cached

needs_cc = pytest.mark.skipif(not compile_cache.compiler_available(), reason="no C compiler")


def logging_compiler(folder, name="cc"):
    """A compiler that appends its arguments to ``calls.log`` beside it, then runs the real one."""
    real = compile_cache.c_compiler()
    path = folder / name
    path.write_text(f'#!/bin/sh\necho "$@" >> "{folder}/calls.log"\nexec "{real}" "$@"\n')
    path.chmod(path.stat().st_mode | stat.S_IEXEC)
    return path


def compiles(folder):
    """The logged compiler calls that compiled a source (``-c``)."""
    log = folder / "calls.log"
    return [line for line in log.read_text().splitlines() if " -c " in f" {line} "] if log.exists() else []


@pytest.fixture
def setup(tmp_path):
    """(logging compiler, cache folder, a C source) in a temporary folder."""
    src = tmp_path / "f.c"
    src.write_text("double f(double x) { return 2.0 * x; }\n")
    return logging_compiler(tmp_path), tmp_path / "cache", src


@needs_cc
def test_an_object_is_compiled_once_and_a_corrupt_entry_is_rebuilt(tmp_path, setup):
    cc, cache, src = setup

    def build(out, flag="-O1"):
        assert compile_cached(str(cache), str(cc), [flag, "-fPIC", "-c", str(src), "-o", str(tmp_path / out)]) == 0
        return (tmp_path / out).read_bytes()

    first = build("a.o")
    assert len(compiles(tmp_path)) == 1
    assert build("b.o") == first and len(compiles(tmp_path)) == 1  # a hit: the compiler did not run
    (entry,) = cache.glob("*/*.o")
    data = bytearray(entry.read_bytes())
    data[-1] ^= 0xFF  # corrupt the object code
    entry.write_bytes(bytes(data))
    assert build("c.o") == first and len(compiles(tmp_path)) == 2  # rebuilt, not trusted
    assert build("d.o") == first and len(compiles(tmp_path)) == 2  # and cached again
    build("e.o", "-O0")  # other flags: another key
    src.write_text("double f(double x) { return 3.0 * x; }\n")
    build("f.o")  # another source: another key
    assert len(compiles(tmp_path)) == 4 and len(list(cache.glob("*/*.o"))) == 3


@needs_cc
def test_a_failing_compile_is_not_cached_and_a_link_is_cached_under_its_object_code(tmp_path, setup):
    cc, cache, src = setup
    src.write_text("this is not C\n")
    assert compile_cached(str(cache), str(cc), ["-c", str(src), "-o", str(tmp_path / "bad.o")]) != 0
    assert not list(cache.glob("*/*.o"))
    src.write_text("double f(double x) { return 2.0 * x; }\n")
    assert compile_cached(str(cache), str(cc), ["-fPIC", "-c", str(src), "-o", str(tmp_path / "f.o")]) == 0
    links = lambda: (tmp_path / "calls.log").read_text().count("-shared")  # noqa: E731

    def link(obj, lib):
        assert compile_cached(str(cache), str(cc), [str(tmp_path / obj), "-o", str(tmp_path / lib), "-shared"]) == 0
        return (tmp_path / lib).read_bytes()

    first = link("f.o", "a.so")
    assert links() == 1 and len(list(cache.glob("*/*.so"))) == 1
    assert link("f.o", "b.so") == first and links() == 1  # a hit: the linker did not run
    assert os.access(tmp_path / "b.so", os.X_OK)
    (entry,) = cache.glob("*/*.so")
    data = bytearray(entry.read_bytes())
    data[-1] ^= 0xFF  # corrupt the library
    entry.write_bytes(bytes(data))
    assert link("f.o", "c.so") == first and links() == 2  # rebuilt, not trusted
    src.write_text("double f(double x) { return 3.0 * x; }\n")
    assert compile_cached(str(cache), str(cc), ["-fPIC", "-c", str(src), "-o", str(tmp_path / "g.o")]) == 0
    assert link("g.o", "d.so") != first and links() == 3  # other object code: another key
    (tmp_path / "h.c").write_text("double h(double x) { return x; }\n")
    assert compile_cached(str(cache), str(cc), ["-fPIC", "-c", str(tmp_path / "h.c"), "-o", str(tmp_path / "h.o")]) == 0
    two = [str(tmp_path / "f.o"), str(tmp_path / "h.o")]
    assert compile_cached(str(cache), str(cc), [*two, "-o", str(tmp_path / "e.so"), "-shared"]) == 0
    assert links() == 4 and len(list(cache.glob("*/*.so"))) == 2  # several objects: run as it is, uncached


@needs_cc
@pytest.mark.skipif(os.name != "posix", reason="the entry lock is POSIX flock")
def test_two_processes_missing_the_same_entry_at_once_compile_it_once(tmp_path, setup):
    """The second process waits for the first one's compile (its entry lock) and takes its entry: the
    compiler, slowed to 1 s so that the two overlap, runs once, both get the same object file, and no
    lock file is left behind."""
    cc, cache, src = setup
    slow = tmp_path / "slowcc"
    slow.write_text(f'#!/bin/sh\nsleep 1\nexec "{cc}" "$@"\n')
    slow.chmod(slow.stat().st_mode | stat.S_IEXEC)
    script = os.path.join(os.path.dirname(compile_cache.__file__), "jitcc.py")
    runs = [subprocess.Popen([sys.executable, "-I", "-S", script, str(cache), str(slow), "-O1", "-fPIC", "-c",
                              str(src), "-o", str(tmp_path / f"{k}.o")]) for k in range(2)]
    assert [r.wait(timeout=60) for r in runs] == [0, 0]
    assert len(compiles(tmp_path)) == 1
    assert (tmp_path / "0.o").read_bytes() == (tmp_path / "1.o").read_bytes()
    assert len(list(cache.glob("*/*.o"))) == 1 and not list(cache.glob("*/*.lock"))


SNIPPET = textwrap.dedent("""
    import casadi as ca
    from pressocp.compile_cache import jit_options
    x = ca.SX.sym("x", 3)
    f = ca.Function("f", [x], [ca.sin(x[0]) * x[1] ** 2 + ca.exp(x[2]) * x[0]], {**jit_options(), "der_options": jit_options()})
    J = ca.Function("J", [x], [ca.jacobian(f(x), x)])
    print(float(f([0.3, 0.5, 0.7])), [float(v) for v in ca.DM(J([0.3, 0.5, 0.7])).full().ravel()])
""")


@needs_cc
def test_a_second_process_with_the_same_function_compiles_nothing(tmp_path):
    """Two processes compile the same function: the first runs the compiler, the second only links,
    and both evaluate what CasADi's virtual machine does."""
    logging_compiler(tmp_path)
    env = {**os.environ, "PATH": f"{tmp_path}{os.pathsep}{os.environ['PATH']}",
           compile_cache.CACHE_ENV: str(tmp_path / "cache")}
    run = lambda: subprocess.run([sys.executable, "-c", SNIPPET], env=env, capture_output=True, text=True,  # noqa: E731
                                 check=True, cwd=tmp_path).stdout
    first = run()
    n = len(compiles(tmp_path))
    assert n >= 1
    assert run() == first and len(compiles(tmp_path)) == n
    import casadi as ca
    x = ca.SX.sym("x", 3)
    e = ca.sin(x[0]) * x[1] ** 2 + ca.exp(x[2]) * x[0]
    vm = ca.Function("vm", [x], [e, ca.jacobian(e, x)])([0.3, 0.5, 0.7])
    expected = f"{float(vm[0])} {[float(v) for v in ca.DM(vm[1]).full().ravel()]}\n"
    assert first == expected


TIMED = SNIPPET.replace("from pressocp.compile_cache import jit_options",
                        "from pressocp.compile_cache import compile_seconds, jit_options") + "print(compile_seconds())\n"


@needs_cc
@pytest.mark.parametrize("cache", ["on", pytest.param("off", marks=pytest.mark.slow)])  # off: 4-12 s
def test_the_compile_time_a_process_reports_is_the_compilers_and_none_for_a_cached_object(tmp_path, cache):
    """`compile_seconds`: a first process's compiles take time; a second one, whose object files all
    come from the cache, reports exactly 0 s, unless the cache is off."""
    env = {**os.environ, compile_cache.CACHE_ENV: str(tmp_path / "cache") if cache == "on" else "off"}
    seconds = [float(subprocess.run([sys.executable, "-c", TIMED], env=env, capture_output=True, text=True,
                                    check=True, cwd=tmp_path).stdout.split()[-1]) for _ in range(2)]
    assert seconds[0] > 0.0
    assert (seconds[1] == 0.0) if cache == "on" else (seconds[1] > 0.0)


def test_the_cache_folder_is_configurable_and_can_be_off(monkeypatch, tmp_path):
    monkeypatch.setenv(compile_cache.CACHE_ENV, str(tmp_path / "here"))
    assert compile_cache.cache_dir() == tmp_path / "here"
    monkeypatch.setenv(compile_cache.CACHE_ENV, "off")
    assert compile_cache.cache_dir() is None
    if compile_cache.compiler_available():  # every compile still timed, none cached
        command = compile_cache.jit_options()["jit_options"]["compiler"]
        assert command.startswith(compile_cache.RECORD_INTERRUPT)  # run through the shell's record of Ctrl-C
        command = command.removeprefix(compile_cache.RECORD_INTERRUPT).split()
        script = next(k for k, a in enumerate(command) if a.endswith("jitcc.py"))
        assert command[script + 1] == compile_cache.NO_CACHE
    monkeypatch.delenv(compile_cache.CACHE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert compile_cache.cache_dir() == tmp_path / "xdg" / "pressocp" / "jit"
    compile_cache.set_cache_dir(tmp_path / "set")
    assert os.environ[compile_cache.CACHE_ENV] == str(tmp_path / "set")


PREPARE = textwrap.dedent("""
    import sys
    from pressocp import Collocation, PressParams, SpeedProblem, WarmStart, build_model, design_speed
    from pressocp.compile_cache import compile_seconds
    problem = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)
    model = build_model(problem.press, clearance=("wrist_pin",), n_harmonics=4)
    speed = design_speed(problem).speed
    tr = Collocation(elements=20, jit=True, ipopt={"ipopt.max_iter": 1})
    if sys.argv[1] == "prepare":
        print(tr.prepare(problem, model, speed))
    else:
        stage = tr.solve(problem, model, WarmStart(speed))
        print(stage.timing["compile"], compile_seconds())
""")


@needs_cc
@pytest.mark.slow  # 34 s; by default: test_a_second_process_with_the_same_function_compiles_nothing
def test_a_solve_after_prepare_in_another_process_compiles_nothing(tmp_path):
    """`Collocation.prepare` compiles what a solve compiles, from the model at rest and without solving:
    a solve in another process then runs the compiler for no source (the compiler's own log), while
    without the preparation the same solve compiles."""
    logging_compiler(tmp_path)
    env = {**os.environ, "PATH": f"{tmp_path}{os.pathsep}{os.environ['PATH']}"}
    run = lambda what, cache: subprocess.run(  # noqa: E731
        [sys.executable, "-c", PREPARE, what], env={**env, compile_cache.CACHE_ENV: str(cache)},
        capture_output=True, text=True, check=True, cwd=tmp_path).stdout.split()
    prepared = float(run("prepare", tmp_path / "cache")[-1])
    n = len(compiles(tmp_path))
    assert prepared > 0.0 and n >= 1
    assert [float(x) for x in run("solve", tmp_path / "cache")] == [0.0, 0.0]
    assert len(compiles(tmp_path)) == n
    unprepared = [float(x) for x in run("solve", tmp_path / "other")]
    assert unprepared[0] > 0.0 and len(compiles(tmp_path)) > n


def test_a_prepared_record_is_named_by_its_parts_and_absent_without_a_cache(monkeypatch, tmp_path):
    monkeypatch.setenv(compile_cache.CACHE_ENV, str(tmp_path))
    a, b = compile_cache.prepared_record("a", "b"), compile_cache.prepared_record("a", "c")
    assert a != b and a == compile_cache.prepared_record("a", "b") and a.parent == tmp_path / "prepared"
    assert not a.exists()
    compile_cache.write_prepared_record(a)
    assert a.exists() and not b.exists()
    monkeypatch.setenv(compile_cache.CACHE_ENV, "off")
    assert compile_cache.prepared_record("a", "b") is None
    compile_cache.write_prepared_record(None)


@needs_cc
def test_derivatives_merge_common_subexpressions_and_keep_every_bit():
    """The compiled functions' derivatives are built with CasADi's cse (`DERIVATIVE_CSE`): the
    collocation point function's Hessian sweep (three forward directions of its adjoint) has fewer
    operations and, evaluated on CasADi's virtual machine, the same values to the bit as without it,
    so IPOPT's path cannot move. The function itself is built without cse."""
    import casadi as ca
    import numpy as np

    import pressocp as po
    from pressocp.model import OUTPUT_NAMES

    options = compile_cache.function_options(True)
    assert options["der_options"]["cse"] is True and "cse" not in options
    assert compile_cache.function_options(True, "quick")["der_options"]["cse"] is True
    model = po.Scenario.load("press75").build_model()
    sweeps = {}
    for cse in (False, True):  # the options without compiling: the same graphs, on the virtual machine
        x, crank, q = ca.SX.sym("x", model.nx), ca.SX.sym("crank", 3), ca.SX.sym("q", len(model.symbols))
        out = model.at_crank(x, crank, q)
        y = ca.vertcat(*[out[1 + OUTPUT_NAMES.index(n)] for n in ("torque", "ram_velocity")])
        f = ca.Function("point", [x, crank, q], [out[0], y], {"der_options": {"cse": cse}})
        sweeps[cse] = f.reverse(1).forward(3)
    assert sweeps[True].n_nodes() < 0.85 * sweeps[False].n_nodes()
    rng = np.random.default_rng(3)
    for _ in range(5):
        args = [rng.standard_normal(sweeps[False].sparsity_in(i).shape) for i in range(sweeps[False].n_in())]
        plain, merged = (np.concatenate([np.ravel(v) for v in sweeps[c].call(args)]) for c in (False, True))
        assert plain.size > 0 and np.array_equal(plain, merged)


NLP_AND_SIMULATION = textwrap.dedent("""
    from pressocp import PressParams, SpeedProblem, build_model
    from pressocp.ocp.rigid_stage import loads_function
    from pressocp.simulate import integrator_dae
    problem = SpeedProblem(PressParams(), period=1.0, ram_speed=-0.15, n_harmonics=4)
    loads_function(problem, jit=True)
    integrator_dae(build_model(problem.press, n_harmonics=4), explicit=False, work=False)
""")


@needs_cc
def test_an_nlps_functions_compile_at_the_nlp_flags_and_a_simulations_at_the_default_ones(tmp_path):
    """The rigid stage's loads compile at `NLP_FLAGS`, an integrator's right-hand side at `FLAGS` (the
    compiler's own log of its calls, in order)."""
    logging_compiler(tmp_path)
    env = {**os.environ, "PATH": f"{tmp_path}{os.pathsep}{os.environ['PATH']}",
           compile_cache.CACHE_ENV: str(tmp_path / "cache")}
    subprocess.run([sys.executable, "-c", NLP_AND_SIMULATION], env=env, capture_output=True, text=True, check=True,
                   cwd=tmp_path)
    calls = compiles(tmp_path)
    assert len(calls) >= 2 and compile_cache.NLP_FLAGS != compile_cache.FLAGS
    nlp, sim = calls[0], calls[-1]
    assert all(f in nlp.split() for f in compile_cache.NLP_FLAGS), nlp
    assert all(f in sim.split() for f in compile_cache.FLAGS), sim
