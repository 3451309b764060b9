"""The numerically exact pipeline: reproducibility, bookkeeping, spectrum cut, CLI output."""

import json
import signal
import subprocess
import sys
import time
from dataclasses import replace

import numpy as np
import pytest

from sealeak.cases import example_path, load_cases, simulate
from sealeak.cases.simulation import JUNCTION_CELLS
from sealeak.cli import main
from sealeak.render import simulation_json, simulation_table
from sealeak.render.simulation import simulation_figures


@pytest.fixture(scope="module")
def case():
    (c,) = load_cases(example_path("reference-experiment"))
    return replace(c, squeeze_pressure=np.array([2e4, 8e4, 3e5]))


def test_simulation_section_gives_defaults_options_override(tmp_path):
    text = example_path("reference-experiment").read_text().replace(
        '{ start = "20 kPa", stop = "250 kPa", num = 40, spacing = "log" }', '["100 kPa"]')
    (tmp_path / "c.toml").write_text(text + '\n[simulation]\ngrid = 16\nrealizations = 1\nseed = 3\n')
    (case,) = load_cases(tmp_path / "c.toml")
    assert case.simulation == {"grid": 16, "realizations": 1, "seed": 3}
    assert main(["simulate", str(tmp_path / "c.toml"), "--no-threshold", "--json", str(tmp_path / "a.json"), "-q"]) == 0
    a = json.loads((tmp_path / "a.json").read_text())
    assert (a["settings"]["grid"], a["settings"]["realizations"], a["settings"]["seed"]) == (16, 1, 3)
    assert main(["simulate", str(tmp_path / "c.toml"), "--no-threshold", "--grid", "32", "--json",
                 str(tmp_path / "b.json"), "-q"]) == 0
    assert json.loads((tmp_path / "b.json").read_text())["settings"]["grid"] == 32
    for bad in ("grid = 15", "grid = 2", "realizations = 0", 'seed = "x"'):
        (tmp_path / "bad.toml").write_text(text + f"\n[simulation]\n{bad}\n")
        assert main(["simulate", str(tmp_path / "bad.toml"), "-q"]) == 2


# ---------------------------------------------------------------- percolation threshold
def _with_pressures(case, pressures):
    return replace(case, squeeze_pressure=np.array(pressures, dtype=float))


def test_threshold_does_not_depend_on_the_listed_pressures(case):
    """Each realisation's threshold is a property of its surface: the same whatever P0 the case lists."""
    lists = ([2e4, 6e4, 1e5, 2e6], [2e4, 6e4, 1.5e5, 4e5], [3e5], [2e5, 2.5e5, 3.5e5, 5e5])
    runs = [simulate(_with_pressures(case, ps), grid=64, realizations=2, seed=5) for ps in lists]
    first = runs[0].per_realization["percolation_threshold"]
    assert np.isfinite(first).all()
    for run in runs[1:]:
        assert np.array_equal(run.per_realization["percolation_threshold"], first)
        assert run.percolation_threshold == runs[0].percolation_threshold
    # and it agrees with the sweep: above the contact area of every pressure at which the fluid still
    # spans, below that of every pressure at which it is blocked (same surface, same solver)
    for run in runs:
        per = run.per_realization
        for r in range(2):
            spanning, blocked = per["relative_contact_area"][r][per["percolates"][r]], per["relative_contact_area"][r][~per["percolates"][r]]
            assert all(a < first[r] for a in spanning) and all(a > first[r] for a in blocked)


# ---------------------------------------------------------------- spreads are standard deviations
@pytest.mark.parametrize("realizations", [1, 3])
def test_spreads_are_standard_deviations_and_labelled_so(case, realizations):
    run = simulate(_with_pressures(case, [3e4, 1e5]), grid=32, realizations=realizations, seed=2)
    per = run.per_realization
    table = simulation_table(case, run)
    if realizations == 1:
        assert np.isnan(run.leak_rate_std).all() and np.isnan(run.percolation_threshold_std)
        assert "one realisation" in table and "nan" not in table
        return
    assert np.allclose(run.leak_rate_std, np.std(per["leak_rate"], axis=0, ddof=1), rtol=1e-12)
    assert np.allclose(run.relative_contact_area_std, np.std(per["relative_contact_area"], axis=0, ddof=1), rtol=1e-12)
    assert run.percolation_threshold_std == pytest.approx(np.std(per["percolation_threshold"], ddof=1), rel=1e-12, abs=0)
    # the table prints these spreads (not sd/√R) and says what they are
    assert f"{run.leak_rate_std[0]:9.2e}".strip() in table
    assert "± sd" in table and "standard deviation over the 3 realisations" in table
    assert f"sd {run.percolation_threshold_std:.2g}" in table
    doc = json.loads(simulation_json(case, run))
    assert doc["results"][0]["leak_rate_std"] == pytest.approx(run.leak_rate_std[0], rel=1e-12, abs=0)
    assert "standard deviations" in doc["spread_note"]


# ---------------------------------------------------------------- a grid too coarse for the pressures
@pytest.mark.parametrize("grid", [32, 40])
def test_coarse_grid_names_the_grid_not_round_off(grid, tmp_path, capsys):
    """On a coarse grid the theory's junction moves to the end of the resolved band at the higher
    pressures (u_c → 0 there): the run completes, α is flagged where λc spans fewer than 8 cells and
    missing where u_c vanishes, and the note names the grid as the input at fault."""
    out = tmp_path / "s.json"
    assert main(["simulate", "--example", "reference-experiment", "--grid", str(grid), "--realizations", "1",
                 "--no-threshold", "--json", str(out)]) == 0
    captured = capsys.readouterr()
    assert "round-off" not in captured.out + captured.err
    notes = [ln for ln in captured.out.splitlines() if ln.startswith(f"note: grid = {grid}:")]
    assert len(notes) == 1 and "--grid" in notes[0] and "fewer than 8 cells" in notes[0]
    rows = json.loads(out.read_text())["results"]
    cells = np.array([np.nan if r["junction_cells"] is None else r["junction_cells"] for r in rows])
    resolved = np.array([r["junction_resolved"] is True for r in rows])
    assert all((r["junction_resolved"] is None) == (r["junction_cells"] is None) for r in rows)
    q_cj = np.array([np.nan if r["leak_rate_critical_junction"] is None else r["leak_rate_critical_junction"] for r in rows])
    # N/ζc falls with pressure (ζc grows); flagged are exactly the pressures below 8 cells, the highest ones
    ok = np.isfinite(cells)
    assert np.all(np.diff(cells[ok]) < 0)
    assert np.array_equal(~resolved[ok], cells[ok] < 8)
    assert resolved[0] and not resolved[ok][-1]
    assert (q_cj[resolved] > 0).all()
    table_rows = [ln for ln in captured.out.splitlines() if ln[:9].strip().replace(".", "").isdigit()]
    assert sum("*" in ln for ln in table_rows) == sum(1 for r in rows if r["junction_resolved"] is False and r["alpha"] is not None)
    if grid == 32:  # the junction reaches the very end of the band: u_c = 0, no Q_cj and no α
        missing = ok & np.isnan(q_cj)
        assert missing.any() and all(rows[i]["alpha"] is None for i in np.flatnonzero(missing))
        assert "no critical-junction leak rate and no α" in notes[0]


# ---------------------------------------------------------------- --fields that cannot be a folder
@pytest.mark.parametrize("layout", ["file", "file/sub", "file/sub/deeper"])
def test_fields_that_is_a_file_is_refused(layout, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # paths relative to it: a message cuts a value at 80 characters, a long tmp_path too
    blocker = tmp_path / "file"
    blocker.write_text("keep me\n")
    js = tmp_path / "s.json"
    assert main(["simulate", "--example", "reference-experiment", "--grid", "16", "--fields", layout,
                 "--json", str(js), "--force"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"--fields = '{layout}'" in err and "not a folder" in err
    assert blocker.read_text() == "keep me\n" and not js.exists()


def test_fields_folder_with_field_files_needs_force(tmp_path, capsys):
    """An earlier run's field files are not replaced without --force: one line naming them, exit 2, nothing written
    (other files in the folder do not count)."""
    folder = tmp_path / "fields"
    folder.mkdir()
    (folder / "r0-p1.npz").write_bytes(b"earlier run")
    (folder / "notes.txt").write_text("mine\n")
    js = tmp_path / "s.json"
    args = ["simulate", "--example", "reference-experiment", "--grid", "16", "--realizations", "1", "--no-threshold",
            "--fields", str(folder), "--json", str(js)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert str(folder / "r0-p1.npz") in err and "--force" in err
    assert (folder / "r0-p1.npz").read_bytes() == b"earlier run" and not js.exists()
    (folder / "r0-p1.npz").unlink()  # only other files there: the run goes ahead
    assert main([*args, "-q"]) == 0
    assert (folder / "notes.txt").read_text() == "mine\n" and (folder / "r0-p0.npz").is_file()


# ---------------------------------------------------------------- Ctrl-C leaves no field files
def _interrupt_after_first_field(args, folder, cwd):
    """Run ``sealeak simulate`` in a subprocess and send SIGINT once its first field file exists."""
    # SIGINT as a terminal sends it, also where this suite runs in a background job (which ignores SIGINT, and a
    # Python started with it ignored never raises KeyboardInterrupt)
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from sealeak.cli import main; sys.exit(main())", *args], cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if any(folder.glob(".sealeak-fields-*/*.npz")):
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, err


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
@pytest.mark.parametrize("existing", [False, True])
def test_interrupted_fields_leave_nothing(existing, tmp_path):
    folder = tmp_path / "out" / "fields"
    old = {}
    if existing:  # an earlier run's field files, replaced with --force only when the new run completes
        folder.mkdir(parents=True)
        for name in ("r0-p0.npz", "r0-p1.npz"):
            (folder / name).write_bytes(b"earlier run")
            old[name] = b"earlier run"
    args = ["simulate", "--example", "reference-experiment", "--grid", "64", "--realizations", "8",
            "--no-threshold", "--fields", str(folder), "--force"]
    rc, err = _interrupt_after_first_field(args, folder, tmp_path)
    assert rc == 130
    assert err.strip().splitlines()[-1] == "sealeak: interrupted; no output was left half-written (outputs completed before the interruption remain)"
    if existing:
        assert {p.name: p.read_bytes() for p in folder.iterdir()} == old
    else:
        assert not (tmp_path / "out").exists()


def test_fields_written_complete_and_in_place(tmp_path):
    folder = tmp_path / "a" / "fields"
    assert main(["simulate", "--example", "reference-experiment", "--grid", "16", "--realizations", "2",
                 "--no-threshold", "--fields", str(folder), "-q"]) == 0
    (case,) = load_cases(example_path("reference-experiment"))
    names = sorted(p.name for p in folder.iterdir())
    assert names == sorted(f"r{r}-p{i}.npz" for r in range(2) for i in range(len(case.squeeze_pressure)))


def test_alpha_figure_with_only_coarse_rows_draws_every_flagged_alpha(tmp_path):
    """No α the grid resolves, so no range to clip the flagged ones to: each is drawn (hollow), none off scale."""
    text = example_path("reference-experiment").read_text()
    text = "\n".join('squeeze_pressure = ["100 kPa", "300 kPa"]' if ln.startswith("squeeze_pressure =") else ln
                     for ln in text.splitlines())
    (tmp_path / "c.toml").write_text(text)
    (case,) = load_cases(tmp_path / "c.toml")
    res = simulate(case, grid=32, realizations=1, seed=0, threshold=False)
    coarse = np.isfinite(res.junction_cells) & (res.junction_cells < JUNCTION_CELLS)
    flagged = np.isfinite(res.alpha) & coarse
    assert flagged.any() and not (np.isfinite(res.alpha) & ~coarse).any()
    ax = simulation_figures(case, res)["simulate_alpha.png"].axes[0]
    hollow = [ln for ln in ax.get_lines() if ln.get_marker() == "o" and ln.get_markerfacecolor() == "none"]
    assert len(hollow) == 1 and "off scale" not in hollow[0].get_label()
    np.testing.assert_array_equal(hollow[0].get_ydata(), res.alpha[flagged])
    assert ax.get_ylim()[1] >= res.alpha[flagged].max()
