"""What the sidebar panels share: the "Roads" tab, long messages as several labels, the
lists with a colour swatch and columns, the constraints of Analyze and Learn, and the run
button of a modal job."""

from ..core.text import wrap


class RoadsTab:
    """Where the panels are: the "Roads" tab of the 3D view's sidebar."""

    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Roads"


def wrapped_labels(layout, text, width=48):
    """Long messages as several labels (a label does not wrap)."""
    for line in wrap(text, width):
        layout.label(text=line)


def columns_of(layout, columns):
    """Sub-layouts for a list's ``columns`` ((header, width) pairs; nested splits, as
    UILayout.split takes one factor)."""
    cells = []
    rest = layout
    for _name, factor in columns[:-1]:
        split = rest.split(factor=factor, align=True)
        cells.append(split.row(align=True))
        rest = split
    cells.append(rest.row(align=True))
    return cells


def swatch_cells(layout, item, columns):
    """A row of a list: the colour swatch of ``item``, then a cell per column."""
    row = layout.row(align=True)
    swatch = row.row(align=True)
    swatch.ui_units_x = 0.8
    swatch.prop(item, "color", text="")
    return columns_of(row, columns)


def header(layout, columns):
    """The headers of a list's ``columns``, after the space of the colour swatch."""
    row = layout.row(align=True)
    spacer = row.row(align=True)
    spacer.ui_units_x = 0.8
    spacer.label(text="")
    for cell, (name, _factor) in zip(columns_of(row, columns), columns):
        cell.label(text=name)


def constraints(col, settings):
    """The constraints of Analyze or Learn (``settings``), under a toggle."""
    col.prop(settings, "show_constraints", icon='TRIA_DOWN' if settings.show_constraints else 'TRIA_RIGHT',
             emboss=False)
    if settings.show_constraints:
        col.prop(settings, "min_aspect")
        col.prop(settings, "min_leaves")
        col.prop(settings, "min_irregularity")


def job_progress(box, operator, graph):
    """The progress of the job of the modal ``operator`` (a jobs.ModalJobOperator) running on
    ``graph`` (or of a jobs.ModalRenderOperator rendering the scene ``graph``); False (nothing
    drawn) when none runs."""
    job = operator._running.get(graph.name) if graph is not None else None
    if job is None:
        return False
    col = box.column(align=True)
    col.label(text="{} ({:.0f}%)".format(job.message, 100.0 * job.fraction), icon='SORTTIME')
    col.label(text="Cancelling\u2026" if job.cancelled else "Esc cancels")
    return True


def run_button(box, graph, settings, operator, icon='PLAY'):
    """The progress of the job of the modal ``operator`` (a jobs.ModalJobOperator) running on
    ``graph``, else its button with the panel's ``settings``."""
    if not job_progress(box, operator, graph):
        row = box.row()
        row.enabled = graph is not None
        op = row.operator(operator.bl_idname, icon=icon)
        for name in operator._FROM_SETTINGS:
            setattr(op, name, getattr(settings, name))
