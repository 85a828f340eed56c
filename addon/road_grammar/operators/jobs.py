"""The modal operator that runs a long native call (Analyze, Learn, Grow into Region, Stitch
Cities, Build City) from the UI, in a worker thread (core.jobs.NativeJob).

The native functions release the GIL; the thread touches no Blender data: its progress
callback (``NativeJob.__call__``) only records the fraction and message and returns False
once the user cancelled. From the UI the operator is modal (a timer shows the progress in
the status bar; Esc or a right click cancels; the viewport can still be navigated); from
scripts and in background mode it waits for the thread, with the window manager's
progress. Nothing in the scene changes before the call has finished (``_finish``, then the
operator's ``_keep``), so a failed or cancelled run leaves it as it was.
"""

import bpy

from ..core.jobs import stop_all as stop_jobs
from ..data import analysis, roads

# Events a running modal job lets through to the viewport: navigation only.
NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'WHEELINMOUSE', 'WHEELOUTMOUSE', 'TRACKPADPAN',
              'TRACKPADZOOM', 'MOUSEROTATE', 'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE', 'NDOF_MOTION', 'TIMER_REPORT',
              'TIMER_REGION', 'TIMER_AUTOSAVE', 'WINDOW_DEACTIVATE', 'NONE'}


def _status_text(context, text):
    """Show ``text`` in the status bar (None: Blender's own again) and redraw the 3D views."""
    if context.workspace is not None:
        context.workspace.status_text_set(text)
    for area in context.screen.areas if context.screen is not None else ():
        if area.type == 'VIEW_3D':
            area.tag_redraw()


class ModalJobOperator:
    """The running of a core.jobs.NativeJob for an operator (a mixin before
    bpy.types.Operator).

    The operator provides:

    * ``_running``: the dict object name -> job of its kind (for the panel, and for poll:
      one object is not worked on twice at once);
    * ``_settings(context)``: the property group whose values ``_FROM_SETTINGS`` are taken
      when invoked (for those not set by the caller): property names, or a dict property
      name -> setting name;
    * ``_start(context)``: read the graph (main thread), set ``_ggg``, ``_object_name``,
      ``_topology`` (the analysis.MeshTopology read, or anything with the ``checksum`` of
      the graph's vertex ids it gives) and start ``_job``; False after an ERROR report;
    * ``_keep(context, obj, topology)``: store the result of the finished job on the road
      graph ``obj`` (main thread; ``_finish`` has checked that the job succeeded and that
      ``obj``, read again as ``topology``, has not changed), report, and return the
      operator's result;
    * ``_doing`` ("Analysing"), ``_noun`` ("the analysis"), ``_progress_label``
      ("Analysing roads"): for the status bar, the console and the messages;
    * the words of ``_finish``'s messages, "{}" standing for the object's name:
      ``_subject`` ("The analysis of {}" was cancelled, failed), ``_cannot`` ("Cannot
      analyse {}": the library's error), ``_result_noun`` ("the analysis" is not kept) and
      ``_changed`` ("{} changed during the analysis; analyse it again").

    It may override ``_report_error(error)`` (the job failed: say why) and
    ``_gone(context)`` (a message when something else the result depends on is gone or has
    changed meanwhile, else None).
    """

    _running = {}
    _FROM_SETTINGS = ()
    _doing = "Working on"
    _noun = "the job"
    _progress_label = "Working"
    _subject = "The job on {}"
    _cannot = "Cannot work on {}"
    _result_noun = "the result"
    _changed = "{} changed during the job; run it again"

    # Set up by _start; an operator instance runs one job.
    _ggg = None
    _job = None
    _timer = None
    _object_name = ""
    _topology = None
    _progress_shown = False

    @classmethod
    def poll(cls, context):
        obj = roads.road_graph_object(context.active_object)
        return obj is None or obj.name not in cls._running

    def _settings(self, context):
        raise NotImplementedError

    def invoke(self, context, event):
        settings = self._settings(context)
        names = self._FROM_SETTINGS
        pairs = names.items() if isinstance(names, dict) else ((name, name) for name in names)
        for name, setting in pairs:
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, setting))
        if bpy.app.background or context.window is None:
            return self.execute(context)
        if not self._start(context):
            return {'CANCELLED'}
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0.0, 1.0)
        self._progress_shown = True
        self._running[self._object_name] = self._job
        self._show_status(context)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        try:
            if event.type == 'TIMER':
                # Ours or another one's (an event does not say which): look, and pass it on.
                if self._job.done():
                    return self._end_modal(context)
                self._show_status(context)
                return {'PASS_THROUGH'}
            if event.type in {'ESC', 'RIGHTMOUSE'} and event.value == 'PRESS':
                self._job.cancel()
                self._show_status(context)
                return {'RUNNING_MODAL'}
        except Exception as ex:  # never leave a thread or a status text behind
            self._job.cancel()
            self._job.join()
            self._cleanup(context)
            self.report({'ERROR'}, "{} failed: {}: {}".format(self._noun.capitalize(), type(ex).__name__, ex))
            return {'CANCELLED'}
        if event.type in NAVIGATION:
            return {'PASS_THROUGH'}
        return {'RUNNING_MODAL'}

    def cancel(self, context):
        # Blender ends the operator (e.g. a file is loaded or Blender quits): stop the
        # thread and wait for it, changing nothing.
        if self._job is not None:
            self._job.cancel()
            self._job.join()
        self._cleanup(context)

    def execute(self, context):
        if not self._start(context):
            return {'CANCELLED'}
        progress = roads.Progress(context, read_share=1.0, label=self._progress_label)
        with progress:
            try:
                while not self._job.wait(0.1):
                    progress.step(self._job.fraction, self._job.message)
            except KeyboardInterrupt:
                self._job.cancel()
                self._job.join()
            progress.step(1.0, "done")
        return self._finish(context)

    def _show_status(self, context):
        job = self._job
        wm = context.window_manager
        wm.progress_update(job.fraction)
        text = "{} {}: {} ({:.0f}%) \u2014 Esc to cancel".format(self._doing, self._object_name, job.message,
                                                                  100.0 * job.fraction)
        if job.cancelled:
            text = "Cancelling {} of {}\u2026".format(self._noun, self._object_name)
        _status_text(context, text)

    def _cleanup(self, context):
        self._running.pop(self._object_name, None)
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        if self._progress_shown:
            wm.progress_end()
            self._progress_shown = False
        _status_text(context, None)

    def _end_modal(self, context):
        self._job.join()
        self._cleanup(context)
        return self._finish(context)

    def _finish(self, context):
        """Check the finished job (main thread) and hand its result to ``_keep``: a job
        cancelled, failed, or whose road graph is gone or changed meanwhile is reported and
        changes nothing ({'CANCELLED'})."""
        ggg, job = self._ggg, self._job
        job.join()
        name = self._object_name
        if isinstance(job.error, ggg.Cancelled):
            self.report({'WARNING'}, "{} was cancelled; nothing changed".format(self._subject.format(name)))
            return {'CANCELLED'}
        if job.error is not None:
            self._report_error(job.error)
            return {'CANCELLED'}
        obj = bpy.data.objects.get(name)
        if obj is None or obj.type != 'MESH':
            self.report({'ERROR'}, "The road graph {} is gone; {} is not kept".format(name, self._result_noun))
            return {'CANCELLED'}
        topology = analysis.MeshTopology(obj)
        if topology.checksum != self._topology.checksum:
            self.report({'ERROR'}, self._changed.format(name))
            return {'CANCELLED'}
        problem = self._gone(context)
        if problem is not None:
            self.report({'ERROR'}, problem)
            return {'CANCELLED'}
        return self._keep(context, obj, topology)

    def _report_error(self, error):
        """Report why the job failed (main thread)."""
        name = self._object_name
        if isinstance(error, self._ggg.Error):
            self.report({'ERROR'}, "{}: {}".format(self._cannot.format(name), error))
        else:
            self.report({'ERROR'}, "{} failed: {}: {}".format(self._subject.format(name), type(error).__name__, error))

    def _gone(self, context):
        """A message when something besides the road graph that the result depends on is gone
        or has changed since the start, else None."""
        return None


def stop_all():
    """Cancel the jobs running in the UI, of every kind, and wait for their threads (the
    add-on is being disabled)."""
    for operator in ModalJobOperator.__subclasses__():
        stop_jobs(operator._running)
