"""core.jobs: a native call in a worker thread, its progress and its cancelling."""

import threading

from road_grammar.core import jobs


class Counting(jobs.NativeJob):
    """Calls the progress callback until told to stop (as the library does)."""

    def _call(self, ggg, graph, options):
        for step in range(options["steps"]):
            if not self(step / options["steps"], "step {}".format(step)):
                raise RuntimeError("cancelled")
            if options.get("wait") is not None:
                options["wait"].wait(1.0)
        return graph * 2


def test_a_job_runs_and_keeps_its_result():
    job = Counting(None, 21, {"steps": 3})
    job.start()
    assert job.wait(10.0)
    job.join()
    assert job.done() and job.result == 42 and job.error is None
    assert job.calls == 3 and job.message == "step 2" and 0.0 <= job.fraction <= 1.0


def test_a_cancelled_job_keeps_the_error():
    gate = threading.Event()
    job = Counting(None, 1, {"steps": 1000, "wait": gate})
    job.start()
    job.cancel()
    gate.set()
    job.join()
    assert job.cancelled and isinstance(job.error, RuntimeError) and job.result is None


def test_stop_all():
    gate = threading.Event()
    running = {"a": Counting(None, 1, {"steps": 1000, "wait": gate}), "b": Counting(None, 2, {"steps": 1000})}
    for job in running.values():
        job.start()
    gate.set()
    jobs.stop_all(running)
    assert all(job.done() for job in running.values())


def test_the_progress_is_clamped():
    job = Counting(None, 1, {"steps": 1})
    assert job(1.5, "over") is True and job.fraction == 1.0
    assert job(-1, "under") is True and job.fraction == 0.0
    job.cancel()
    assert job(0.5, "cancelled") is False
