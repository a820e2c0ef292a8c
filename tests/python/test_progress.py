"""Long work: progress reaches a callback (or tqdm, or stderr) on the calling thread, other Python
threads run while the library works, and a callback that raises or Ctrl-C stops the work cleanly:
the exception comes out, and no partial output or temporary stays behind."""

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
import types

import pytest

import brdfbake
from conftest import PHONG_EYE

# A bake that takes a few seconds on one thread (a 1024^2 map, 64 samples per texel).
SLOW = dict(PHONG_EYE, output="slow.exr", resolution=1024, samples_per_texel=64,
            material={"model": "blinn_phong", "specular": [1, 1, 1], "exponent": 50, "diffuse": [0.5, 0.5, 0.5]},
            lights=[{"direction": [1, 1, 1], "color": [1, 1, 1]}, {"direction": [-1, 0, 1], "color": [1, 1, 1]}])


def test_progress_reaches_the_callback_on_the_calling_thread(tmp_path):
    calls = []
    spec = {"maps": [PHONG_EYE, dict(PHONG_EYE, output="second.exr", resolution=64)]}

    def progress(task, fraction):
        calls.append((task, fraction, threading.current_thread() is threading.main_thread()))

    brdfbake.bake(spec, out_dir=tmp_path, progress=progress)
    tasks = list(dict.fromkeys(task for task, _, _ in calls))
    assert tasks == ["maps[0] phong_eye.exr", "maps[1] second.exr"]
    for task in tasks:
        fractions = [f for t, f, _ in calls if t == task]
        assert fractions == sorted(fractions) and fractions[-1] == 1.0 and 0 <= fractions[0]
    assert all(on_main for _, _, on_main in calls)


def test_a_callback_that_raises_stops_the_work_and_leaves_nothing(tmp_path):
    class Stop(Exception):
        pass

    def progress(task, fraction):
        raise Stop(task)

    with pytest.raises(Stop):
        brdfbake.bake({"maps": [SLOW]}, out_dir=tmp_path, threads=1, progress=progress)
    assert list(tmp_path.iterdir()) == []


def test_other_python_threads_run_while_the_library_works(tmp_path):
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    thread = threading.Thread(target=tick)
    start = time.monotonic()
    thread.start()
    try:
        brdfbake.bake({"maps": [dict(SLOW, resolution=512, samples_per_texel=16)]}, out_dir=tmp_path, threads=1,
                      progress=False)
    finally:
        stop.set()
        thread.join()
    seconds = time.monotonic() - start
    # Holding the GIL, the bake would leave the thread one tick per switch interval (5 ms) at most.
    assert len(ticks) > seconds / 0.005 * 2, f"{len(ticks)} ticks in {seconds:.2f} s"


def test_tqdm_bars_when_tqdm_is_installed(tmp_path, monkeypatch):
    bars = []

    class Bar:
        def __init__(self, total, desc, unit, leave):
            self.total, self.desc, self.n, self.closed = total, desc, 0, False
            bars.append(self)

        def refresh(self):
            assert 0 <= self.n <= self.total

        def close(self):
            self.closed = True

    module = types.ModuleType("tqdm.auto")
    module.tqdm = Bar
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", module)
    brdfbake.bake({"maps": [dict(PHONG_EYE, resolution=64)]}, out_dir=tmp_path, progress=True)
    assert [b.desc for b in bars] == ["maps[0] phong_eye.exr"]
    assert bars[0].n == 100 and bars[0].closed


def test_lines_on_stderr_without_tqdm(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm raises ImportError
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    brdfbake.bake({"maps": [dict(PHONG_EYE, resolution=64)]}, out_dir=tmp_path, progress=True)
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1] == "brdfbake: maps[0] phong_eye.exr: 100%"
    brdfbake.bake({"maps": [dict(PHONG_EYE, output="quiet.exr", resolution=64)]}, out_dir=tmp_path)
    assert capsys.readouterr().err == ""  # the default: bars only on a terminal with tqdm


@pytest.mark.parametrize("job", ["bake", "fit", "matcap", "prefilter", "ibl"])
def test_ctrl_c_stops_the_work_cleanly(tmp_path, source_dir, job):
    # In a child interpreter, as a user would press Ctrl-C: SIGINT half a second into the work; the call
    # returns with KeyboardInterrupt within a second and a half of it.
    table = source_dir / "data_samples" / "tables" / "synthetic_varying.astm"
    sky = str(source_dir / "data_samples" / "environments" / "sky_latlong.exr")
    out = str(tmp_path / "out")
    work = {
        "bake": f"brdfbake.bake({{'maps': [{SLOW!r}]}}, out_dir={out!r}, threads=1, progress=started)",
        "fit": f"brdfbake.fit({str(table)!r}, method='per_channel', lobes=3, elevation='varying', threads=1, "
        f"output={out + '/fit.json'!r}, progress=started)",
        "matcap": f"brdfbake.matcap({{'model': 'phong', 'specular': [1, 1, 1], 'exponent': 200}}, {sky!r}, 512, "
        f"method='reference', threads=1, output={out + '/m.exr'!r}, progress=started)",
        "prefilter": f"brdfbake.prefilter({sky!r}, 'phong:100', 'cube', 256, method='reference', threads=1, "
        f"output={out + '/p.exr'!r}, progress=started)",
        "ibl": f"brdfbake.ibl({sky!r}, resolution=512, max_error=0.002, threads=1, progress=started).save({out!r})",
    }[job]
    script = textwrap.dedent(f"""
        import sys, brdfbake
        def started(task, fraction):
            if not getattr(started, "said", False):
                started.said = True
                print("started", flush=True)
        try:
            {work}
        except KeyboardInterrupt:
            print("KeyboardInterrupt", flush=True)
            sys.exit(130)
        print("finished", flush=True)
    """)
    (tmp_path / "out").mkdir()
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ))
    assert child.stdout.readline().strip() == "started"
    time.sleep(0.5)
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=60)
    stopped = time.monotonic() - sent
    assert child.returncode == 130, out + err
    assert out.strip() == "KeyboardInterrupt"
    assert stopped < 1.5, f"stopped {stopped:.1f} s after SIGINT"
    assert list((tmp_path / "out").iterdir()) == []


def test_a_callback_raising_at_a_maps_last_report_stops_it_before_it_is_written(tmp_path):
    # A task's last report (fraction 1) waits for the callback, and comes before the map is written:
    # raising there leaves the map unwritten, whatever the threads' timing. The map before it stays.
    class Stop(Exception):
        pass

    seen = []

    def progress(task, fraction):
        seen.append((task, fraction))
        if task.startswith("maps[1]") and fraction >= 1.0:
            raise Stop(task)

    spec = {"maps": [dict(PHONG_EYE, output="first.exr", resolution=64), dict(PHONG_EYE, output="second.exr", resolution=64)]}
    for _ in range(5):
        with pytest.raises(Stop):
            brdfbake.bake(spec, out_dir=tmp_path, threads=2, progress=progress)
        assert sorted(p.name for p in tmp_path.iterdir()) == ["first.exr"]
        (tmp_path / "first.exr").unlink()
    assert ("maps[0] first.exr", 1.0) in seen and ("maps[1] second.exr", 1.0) in seen


def test_a_callback_is_called_a_few_times_a_second_not_per_row(tmp_path):
    calls = []
    brdfbake.bake({"maps": [dict(SLOW, resolution=512, samples_per_texel=4)]}, out_dir=tmp_path, threads=1,
                  progress=lambda task, fraction: calls.append(time.monotonic()))
    seconds = calls[-1] - calls[0]
    assert len(calls) <= seconds / 0.05 + 3, f"{len(calls)} calls in {seconds:.2f} s"
