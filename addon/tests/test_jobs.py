"""core.jobs: a native call in a worker thread, its progress and its cancelling; what Blender's
render job did, as its handlers tell (RenderProgress)."""

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


class FakeLibrary:
    """What a StepsJob needs of ggg: its Cancelled."""

    class Cancelled(Exception):
        pass


class Recording(jobs.StepsJob):
    """A StepsJob that keeps every progress report."""

    def __init__(self, work):
        super().__init__(FakeLibrary, work)
        self.seen = []

    def __call__(self, fraction, message):
        self.seen.append((round(fraction, 6), message))
        return super().__call__(fraction, message)


def test_steps_share_the_progress_bar():
    def work(job):
        job.step(0.0, "reading")
        progress = job.stage(0.2, 0.6, "growing")
        for fraction, message in ((0.5, "placing"), (0.25, "placing"), (1.0, "done")):
            assert progress(fraction, message)
        job.step(1.0, "done")
        return "grown"

    job = Recording(work)
    job.start()
    job.join()
    assert job.result == "grown" and job.error is None
    # (0.25 after 0.5: the bar stays where it was.)
    assert job.seen == [(0.0, "reading"), (0.2, "growing: starting"), (0.4, "growing: placing"),
                        (0.4, "growing: placing"), (0.6, "growing: done"), (1.0, "done")]


def test_a_cancelled_steps_job_stops_at_the_next_step():
    gate = threading.Event()
    reached = []

    def work(job):
        job.step(0.1, "first")
        gate.wait(10.0)
        reached.append("after the wait")
        job.step(0.5, "second")
        reached.append("after the second step")
        return "done"

    job = jobs.StepsJob(FakeLibrary, work)
    job.start()
    job.cancel()
    gate.set()
    job.join()
    assert isinstance(job.error, FakeLibrary.Cancelled) and job.result is None
    assert reached == ["after the wait"]


def test_a_cancelled_stage_tells_the_library_to_stop():
    def work(job):
        progress = job.stage(0.0, 1.0)
        job.cancel()
        return progress(0.5, "placing")

    job = jobs.StepsJob(FakeLibrary, work)
    job.start()
    job.join()
    assert job.result is False and job.cancelled


# --- RenderProgress: Blender's render job, from its handlers -------------------------------------

def test_a_render_that_writes_every_frame_is_rendered():
    render = jobs.RenderProgress("/out/flythrough.mp4", 3)
    assert (render.name, render.message, render.fraction) == ("flythrough.mp4", "frame 1 of 3", 0.0)
    render.on_write(None)  # (Blender passes the scene, and may pass more)
    assert (render.message, render.fraction) == ("frame 2 of 3", 1 / 3)
    render.on_write(None, None)
    render.on_write()
    assert (render.message, render.fraction) == ("finishing", 1.0)
    render.on_complete(None)
    assert not render.cancelled
    assert render.outcome(True) == ('INFO', "Rendered /out/flythrough.mp4")
    # Done, but the file is not there.
    assert render.outcome(False) == ('ERROR', "Rendering wrote no file /out/flythrough.mp4")


def test_a_still_is_one_frame():
    render = jobs.RenderProgress("/out/city.png", 0)
    assert render.frames == 1 and render.message == "frame 1 of 1"
    render.on_write(None)
    render.on_complete(None)
    assert render.outcome(True) == ('INFO', "Rendered /out/city.png")


def test_a_cancelled_render_says_how_far_it_got():
    render = jobs.RenderProgress("/out/flythrough.mp4", 72)
    for _ in range(5):
        render.on_write(None)
    render.on_cancel(None)
    assert render.cancelled
    assert render.outcome(True) == ('WARNING', "Rendering /out/flythrough.mp4 was cancelled after 5 of 72 frames")
    still = jobs.RenderProgress("/out/city.png", 1)
    still.on_cancel(None)
    assert still.outcome(False) == ('WARNING', "Rendering /out/city.png was cancelled")


def test_esc_counts_as_cancelled_unless_every_frame_was_written():
    render = jobs.RenderProgress("/out/flythrough.mp4", 4)
    render.on_write(None)
    render.cancel()  # Esc: Blender stops its render job itself
    assert render.cancelled
    render.on_complete(None)
    assert render.outcome(True) == ('WARNING', "Rendering /out/flythrough.mp4 was cancelled after 1 of 4 frames")
    # Esc came too late to stop anything: the file is complete.
    late = jobs.RenderProgress("/out/flythrough.mp4", 2)
    late.on_write(None)
    late.on_write(None)
    late.cancel()
    late.on_complete(None)
    assert late.outcome(True) == ('INFO', "Rendered /out/flythrough.mp4")


def test_a_render_that_ended_early_is_an_error():
    render = jobs.RenderProgress("/out/flythrough.mp4", 10)
    for _ in range(4):
        render.on_write(None)
    render.on_complete(None)  # (a render job stopped from outside still says "complete")
    assert render.outcome(True) == ('ERROR', "Rendering /out/flythrough.mp4 stopped with 4 of 10 frames written")
