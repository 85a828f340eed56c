"""Long native calls (Analyze, Learn, Grow into Region, Stitch Cities, Build City) in a
worker thread, and what Blender's own render job did for Render City.

The native functions release the GIL; the thread touches no Blender data: its progress
callback (``NativeJob.__call__``) only records the fraction and message and returns False
once the user cancelled. ``operators.jobs.ModalJobOperator`` runs one from the UI.

Blender renders in a thread of its own and calls the render handlers from it; a
``RenderProgress`` takes those calls and, like the progress callback, only records them
(``operators.jobs.ModalRenderOperator`` watches a render from the UI).
"""

import os
import threading
import time

from .text import plural


class NativeJob:
    """One run of a native call in a worker thread (subclasses say which, in ``_call``).

    The thread never touches Blender data. ``__call__`` is the progress callback (called by
    the native library, from any of its threads): it records the fraction and the message
    and tells the library whether to go on."""

    thread_name = "road_grammar job"

    def __init__(self, ggg, graph, options):
        self._ggg = ggg
        self._graph = graph
        self._options = options
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._thread = None
        self.fraction = 0.0
        self.message = "starting"
        self.calls = 0
        self.result = None
        self.error = None
        self.seconds = 0.0

    def _call(self, ggg, graph, options):
        """The native call (worker thread); its result becomes ``result``."""
        raise NotImplementedError

    def keep_going(self):
        return not self._cancel.is_set()

    def __call__(self, fraction, message):
        self.calls += 1
        self.fraction = min(max(float(fraction), 0.0), 1.0)
        self.message = str(message)
        return self.keep_going()

    def _run(self):
        started = time.perf_counter()
        try:
            self.result = self._call(self._ggg, self._graph, self._options)
        except BaseException as ex:  # handed to the main thread, which reports it
            self.error = ex
        finally:
            self.seconds = time.perf_counter() - started
            self._graph = None
            self._done.set()

    def start(self):
        self._thread = threading.Thread(target=self._run, name=self.thread_name, daemon=True)
        self._thread.start()

    def cancel(self):
        self._cancel.set()

    @property
    def cancelled(self):
        return self._cancel.is_set()

    def done(self):
        return self._done.is_set()

    def wait(self, timeout=None):
        return self._done.wait(timeout)

    def join(self):
        if self._thread is not None:
            self._thread.join()


def stop_all(running):
    """Cancel the jobs of ``running`` (object name -> NativeJob) and wait for their threads
    (the add-on is being disabled)."""
    for job in list(running.values()):
        job.cancel()
        job.join()


class AnalysisJob(NativeJob):
    """One run of ggg.analyze in a worker thread."""

    thread_name = "road_grammar analyze"

    def _call(self, ggg, graph, options):
        return ggg.analyze(graph, progress=self, **options)


class LearningJob(NativeJob):
    """One run of ggg.learn in a worker thread."""

    thread_name = "road_grammar learn"

    def _call(self, ggg, graph, options):
        return ggg.learn(graph, progress=self, **options)


class StepsJob(NativeJob):
    """Several native calls, and the bpy-free work between them, in a worker thread: the
    function ``work(job)`` (which touches no Blender data) returns the result.

    Each native call gets its share of the progress bar from ``stage``; ``check`` between
    the calls stops the work once the user cancelled, as the library does (raising
    ``ggg.Cancelled``)."""

    thread_name = "road_grammar steps"

    def __init__(self, ggg, work, thread_name=None):
        super().__init__(ggg, None, None)
        self._work = work
        if thread_name is not None:
            self.thread_name = thread_name

    def _call(self, ggg, graph, options):
        return self._work(self)

    def stage(self, start, end, label=""):
        """The progress callback of one native call whose progress fills [start, end] of the
        whole; its messages are prefixed with ``label``."""
        self.check()
        span = end - start
        prefix = label + ": " if label else ""
        highest = [0.0]

        def progress(fraction, message):
            # (The bar does not go back when the library starts a phase over.)
            highest[0] = max(highest[0], min(max(float(fraction), 0.0), 1.0))
            return self(start + span * highest[0], prefix + str(message))

        progress(0.0, "starting")
        return progress

    def step(self, fraction, message):
        """A step of the work outside the library (the progress of the whole); stops once the
        user cancelled."""
        self(fraction, message)
        self.check()

    def check(self):
        """Raise ggg.Cancelled once the user cancelled."""
        if self.cancelled:
            raise self._ggg.Cancelled("cancelled")


class RenderProgress:
    """What Blender's render job has done for one render to ``path`` of ``frames`` frames (1
    for a still), as its handlers tell: ``on_write`` (render_write: a frame is in the file),
    ``on_complete`` (render_complete) and ``on_cancel`` (render_cancel: the render was
    stopped, by Esc or an error). Blender calls them from its render thread: they only
    record, and the operator reads the record on the main thread. ``cancel`` notes that the
    user pressed Esc (Blender stops its render job itself)."""

    def __init__(self, path, frames):
        self.path = path
        self.frames = max(1, int(frames))
        self.written = 0
        self.completed = False
        self.stopped = False
        self._escaped = False

    def on_write(self, *_args):
        self.written += 1

    def on_complete(self, *_args):
        self.completed = True

    def on_cancel(self, *_args):
        self.stopped = True

    def cancel(self):
        self._escaped = True

    @property
    def cancelled(self):
        """The user pressed Esc, or Blender said the render was cancelled."""
        return self._escaped or self.stopped

    @property
    def name(self):
        """The file's name, for the status bar."""
        return os.path.basename(self.path)

    @property
    def fraction(self):
        return min(self.written / self.frames, 1.0)

    @property
    def message(self):
        if self.written >= self.frames:
            return "finishing"
        return "frame {} of {}".format(self.written + 1, self.frames)

    def outcome(self, file_exists):
        """(report type, message) once the render job has ended; ``file_exists``: whether
        ``path`` is there. 'INFO' when every frame was written, 'WARNING' when the render
        was cancelled, 'ERROR' when it ended without writing them all."""
        if self.completed and not self.stopped and self.written >= self.frames and file_exists:
            return 'INFO', "Rendered {}".format(self.path)
        if self.cancelled:
            if self.frames == 1:
                return 'WARNING', "Rendering {} was cancelled".format(self.path)
            return 'WARNING', "Rendering {} was cancelled after {} of {}".format(
                self.path, self.written, plural(self.frames, "frame"))
        if not file_exists:
            return 'ERROR', "Rendering wrote no file {}".format(self.path)
        return 'ERROR', "Rendering {} stopped with {} of {} written".format(
            self.path, self.written, plural(self.frames, "frame"))
