"""Progress reaches Python (`progress=`): a callable receives every bar's state, each
bar's fraction rises to 1 where its run ends; `progress=False` reports nothing; without
tqdm `progress=True` prints lines on stderr; a callback that raises stops the run as
Ctrl-C does."""
import sys

import pytest

import impact
from impact import _progress


def bars_of(calls):
    """{index: (label, [(fraction, finished), ...])} over every call of the callback."""
    bars = {}
    for updates in calls:
        for index, label, fraction, finished in updates:
            bars.setdefault(index, (label, []))[1].append((fraction, finished))
    return bars


def test_a_callback_sees_each_method_rise_to_the_end():
    calls = []
    res = impact.run("plate", methods=["dgmpm", "mpm"], cells=300, files=False,
                     reference=False, progress=calls.append)
    assert res.failures == []
    bars = bars_of(calls)
    # reports while running (about 2 s here, a report at most every 0.2 s)
    assert any(0.0 < f < 1.0 for _, states in bars.values() for f, _ in states), calls
    assert [bars[i][0] for i in sorted(bars)] == ["dgmpm", "mpm"]
    for label, states in bars.values():
        fractions = [f for f, _ in states]
        assert fractions == sorted(fractions), (label, fractions)
        assert all(0.0 <= f <= 1.0 for f in fractions)
        # the last report: the run reached t_end and its bar is done
        assert states[-1] == (1.0, True), (label, states[-1])
    # every call lists every bar created so far, in creation order
    assert all([u[0] for u in call] == list(range(len(call))) for call in calls)


def test_no_progress_reports_nothing(capfd):
    assert _progress.reporter(False) is None and _progress.reporter(None) is None
    impact.run("bar", methods=["dgmpm"], files=False, progress=False)
    assert capfd.readouterr().err == ""


def test_without_tqdm_progress_prints_lines(capfd, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # import fails: no tqdm
    assert isinstance(_progress.reporter(True), _progress._Lines)
    impact.run("bar", methods=["dgmpm", "mpm"], files=False, reference=False,
               progress=True)
    lines = capfd.readouterr().err.splitlines()
    assert "    dgmpm done" in lines and "      mpm done" in lines, lines


def test_with_tqdm_progress_draws_a_bar_per_method(capfd):
    pytest.importorskip("tqdm")
    drawer = _progress.reporter(True)
    assert isinstance(drawer, _progress._Tqdm)
    impact.run("bar", methods=["dgmpm", "mpm"], files=False, reference=False,
               progress=drawer)
    assert sorted(drawer.closed) == [0, 1]
    assert [bar.n for bar in drawer.bars.values()] == [1000, 1000]
    err = capfd.readouterr().err
    assert "dgmpm" in err and "100%" in err, err
    # a run stopped early: its open bars are closed
    with pytest.raises(KeyboardInterrupt):
        with _progress.reporting(True) as drawer:
            drawer([(0, "dgmpm", 0.5, False)])
            raise KeyboardInterrupt
    assert drawer.closed == {0} and drawer.bars[0].n == 500


def test_check_reports_its_runs():
    calls = []
    doc = impact.check("bar", cells=100, progress=calls.append)
    labels = [label for label, _ in bars_of(calls).values()]
    assert doc["pass"] is True
    assert labels[0] == "dgmpm" and labels.count("mpm") == len(doc["reports"])


def test_a_raising_callback_stops_the_run(tmp_path):
    def stop(updates):
        raise KeyboardInterrupt

    out = tmp_path / "plate"
    with pytest.raises(KeyboardInterrupt):
        impact.run("plate", out=out, cells=300, reference=False, progress=stop)
    assert not out.exists()
    assert impact.run("bar", methods=["dgmpm"], files=False).failures == []
