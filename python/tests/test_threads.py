"""Threads: Engine.surface releases the GIL; two engines in two threads compute at once; one engine
shared by threads takes turns (its lock) and gives the same meshes as one thread."""

import threading

import numpy as np

import fdmsurf


def serial(engine, paths, **keywords):
    return [engine.surface(p, **keywords) for p in paths]


def same(a, b):
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)


def test_the_gil_is_released_while_computing(engine, data):
    done = threading.Event()
    results = []

    def work():
        results.append(engine.surface(data / "4hhb.pdb.gz", spacing=0.5))
        done.set()

    thread = threading.Thread(target=work)
    thread.start()
    spins = 0
    while not done.is_set():
        spins += 1  # runs only while the other thread does not hold the GIL
    thread.join()
    assert results and results[0].closed_manifold
    # Computing 4HHB takes a second or more; a held GIL would leave this loop a few thousand
    # iterations (those between switch intervals) at most.
    assert spins > 100_000, spins


def test_two_engines_in_two_threads(engine, data):
    paths = [data / "1crn.pdb", data / "3al1.pdb", data / "1crn.cif"]
    expected = serial(engine, paths, spacing=0.7)
    outcome = {}

    def work(name):
        with fdmsurf.Engine() as own:
            outcome[name] = serial(own, paths, spacing=0.7)

    threads = [threading.Thread(target=work, args=(n,)) for n in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for name in ("a", "b"):
        for got, want in zip(outcome[name], expected):
            same(got, want)


def test_one_engine_shared_by_threads_takes_turns(engine, data):
    paths = [data / "3al1.pdb", data / "1crn.pdb"]
    expected = serial(engine, paths, spacing=0.8)
    outcome, errors = {}, []

    def work(i):
        try:
            outcome[i] = serial(engine, paths[i % 2:] + paths[:i % 2], spacing=0.8)
        except Exception as e:  # noqa: BLE001 - reported by the assertion below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for i, results in outcome.items():
        order = expected[i % 2:] + expected[:i % 2]
        for got, want in zip(results, order):
            same(got, want)


def test_default_engine_from_threads(data):
    results = [None, None]

    def work(i):
        results[i] = fdmsurf.surface(data / "1crn.pdb", spacing=1.0)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    same(results[0], results[1])
