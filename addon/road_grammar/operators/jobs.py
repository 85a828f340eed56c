"""The modal operators that run a long job from the UI: a native call (Analyze, Learn, Grow
into Region, Stitch Cities, Build City) in a worker thread (core.jobs.NativeJob), and Blender's
own render job (Render City).

The native functions release the GIL; the thread touches no Blender data: its progress
callback (``NativeJob.__call__``) only records the fraction and message and returns False
once the user cancelled. From the UI the operator is modal (a timer shows the progress in
the status bar; Esc or a right click cancels; the viewport can still be navigated); from
scripts and in background mode it waits for the thread, with the window manager's
progress. Nothing in the scene changes before the call has finished (``_finish``, then the
operator's ``_keep``), so a failed or cancelled run leaves it as it was.

A render from the UI is Blender's render job (``ModalRenderOperator``): it renders in a thread
of its own, shows its progress in the status bar and stops on Esc. The operator hands the
render handlers to a core.jobs.RenderProgress, follows it with a timer (frames written, in
the status bar and the panel; Esc to cancel) and reports what was written, or that the
render was cancelled, once the job has ended; from scripts and in background mode it renders
at once (``execute``).
"""

import os

import bpy

from ..core.jobs import RenderProgress
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


def _end_progress(operator, context):
    """Remove a modal operator's timer and progress bar, and give the status bar back."""
    wm = context.window_manager
    if operator._timer is not None:
        wm.event_timer_remove(operator._timer)
        operator._timer = None
    if operator._progress_shown:
        wm.progress_end()
        operator._progress_shown = False
    _status_text(context, None)


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
        _end_progress(self, context)

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


# Blender's render handlers that a RenderProgress takes: handler list -> its method.
RENDER_HANDLERS = (("render_write", "on_write"), ("render_complete", "on_complete"), ("render_cancel", "on_cancel"))

# Renders started from the UI and not yet ended: scene name -> RenderProgress (for the panel,
# and so that one scene is not rendered twice at once).
renders = {}


def _handlers_of(progress):
    return [(getattr(bpy.app.handlers, name), getattr(progress, method)) for name, method in RENDER_HANDLERS]


def watch_render(key, progress):
    """Hand Blender's render handlers to ``progress`` (a RenderProgress) and keep it in
    ``renders`` under ``key``."""
    unwatch_render(key)
    for handlers, method in _handlers_of(progress):
        handlers.append(method)
    renders[key] = progress


def unwatch_render(key):
    """Take the handlers of the render kept under ``key`` out of Blender's lists again (a
    file loaded meanwhile may have cleared them); its RenderProgress, else None."""
    progress = renders.pop(key, None)
    if progress is not None:
        for handlers, method in _handlers_of(progress):
            while method in handlers:
                handlers.remove(method)
    return progress


class ModalRenderOperator:
    """Rendering the scene with Blender's render job (a mixin before bpy.types.Operator).

    The operator provides ``animation`` (a property: the frame range, else a still),
    ``_prepare(context)`` (set the scene up; the path of the file to write, or None after an
    ERROR report) and ``execute`` (the render from scripts and in background mode: it
    waits). From the UI, ``invoke`` starts Blender's render job and returns RUNNING_MODAL;
    ``modal`` follows it until it has ended and reports "Rendered <path>" ({'FINISHED'}),
    that the render was cancelled (a WARNING) or why no file was written (an ERROR; both
    {'CANCELLED'})."""

    _running = renders
    _doing = "Rendering"

    # Set up by invoke; an operator instance watches one render.
    _key = ""
    _timer = None
    _progress_shown = False

    @classmethod
    def poll(cls, context):
        return context.scene is None or context.scene.name not in cls._running

    def _prepare(self, context):
        raise NotImplementedError

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        if bpy.app.is_job_running('RENDER'):
            self.report({'ERROR'}, "Blender is rendering already: wait until it has finished, or press Esc")
            return {'CANCELLED'}
        path = self._prepare(context)
        if path is None:
            return {'CANCELLED'}
        scene = context.scene
        frames = len(range(scene.frame_start, scene.frame_end + 1, scene.frame_step)) if self.animation else 1
        self._key = scene.name
        watch_render(self._key, RenderProgress(path, frames))
        try:
            if self.animation:
                started = bpy.ops.render.render('INVOKE_DEFAULT', animation=True)
            else:
                started = bpy.ops.render.render('INVOKE_DEFAULT', write_still=True)
        except RuntimeError as ex:  # Blender refused, with an error report
            unwatch_render(self._key)
            self.report({'ERROR'}, "Cannot render {}: {}".format(path, ex))
            return {'CANCELLED'}
        if 'RUNNING_MODAL' not in started:
            unwatch_render(self._key)
            self.report({'ERROR'}, "Blender did not start rendering {}".format(path))
            return {'CANCELLED'}
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0.0, 1.0)
        self._progress_shown = True
        self._show_status(context)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        progress = self._running.get(self._key)
        try:
            if progress is None:  # the add-on is being disabled (stop_all)
                self._cleanup(context)
                return {'CANCELLED'}
            if event.type == 'TIMER':
                # Ours or another one's (an event does not say which): look, and pass it on.
                if not bpy.app.is_job_running('RENDER'):
                    return self._end(context)
                self._show_status(context)
            elif event.type == 'ESC' and event.value == 'PRESS':
                # Blender stops its render job on Esc; until it has, the status says so.
                progress.cancel()
                self._show_status(context)
        except Exception as ex:  # never leave handlers or a status text behind
            self._cleanup(context)
            self.report({'ERROR'}, "Rendering failed: {}: {}".format(type(ex).__name__, ex))
            return {'CANCELLED'}
        # Everything goes on to Blender (its render job takes Esc too): the UI stays usable.
        return {'PASS_THROUGH'}

    def cancel(self, context):
        # Blender ends the operator (a file is loaded, Blender quits; it stops its render job).
        self._cleanup(context)

    def _show_status(self, context):
        progress = self._running.get(self._key)
        if progress is None:
            return
        context.window_manager.progress_update(progress.fraction)
        text = "{} {}: {} ({:.0f}%) \u2014 Esc to cancel".format(self._doing, progress.name, progress.message,
                                                                100.0 * progress.fraction)
        if progress.cancelled:
            text = "Cancelling the render of {}\u2026".format(progress.name)
        _status_text(context, text)

    def _cleanup(self, context):
        unwatch_render(self._key)
        _end_progress(self, context)

    def _end(self, context):
        """The render job has ended: report what it wrote (main thread)."""
        progress = self._running.get(self._key)
        self._cleanup(context)
        kind, message = progress.outcome(os.path.isfile(progress.path))
        self.report({kind}, message)
        return {'FINISHED'} if kind == 'INFO' else {'CANCELLED'}


def stop_all():
    """Cancel the jobs running in the UI, of every kind, and wait for their threads; stop
    watching the renders (Blender's render job goes on by itself) (the add-on is being
    disabled)."""
    for operator in ModalJobOperator.__subclasses__():
        stop_jobs(operator._running)
    for key in list(renders):
        unwatch_render(key)
