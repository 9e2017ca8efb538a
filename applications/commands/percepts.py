"""`interbot percepts [--robot R] [--app APP]`: every percept a condition may read, with its type,
unit, range and meaning, and which plugin declares it."""
from __future__ import annotations

from behaviors import robot_capabilities
from behaviors.percepts import TIME_IN_STATE, percept_catalog


class PerceptsCommand:
    name = "percepts"
    help = "list the percepts conditions may read (type, unit, range, meaning)"

    def add_arguments(self, parser) -> None:
        parser.add_argument("--robot", help="mark the percepts this robot cannot provide")
        parser.add_argument("--app", help="also list an application's answer.<id> percepts "
                            "and its parameters (param.<name>)")

    def run(self, args) -> int:
        catalog = percept_catalog()
        capabilities = robot_capabilities(args.robot) if args.robot else None
        needs = {provider.name: provider.needs for provider in catalog.providers}
        rows = [(spec, capabilities is None or needs[spec.provider] <= capabilities)
                for spec in catalog.specs.values()]
        rows.append((TIME_IN_STATE, True))
        if args.app:
            rows += [(spec, True) for spec in _answers(args.app)]
        for spec, available in sorted(rows, key=lambda row: row[0].name):
            print(describe(spec) + ("" if available else f"   [not on {args.robot}]"))
        for plugin, problem in sorted(catalog.problems.items()):
            print(f"warning: percept plugin '{plugin}' is not available: {problem}")
        return 0


def describe(spec) -> str:
    kind = spec.type + (f" [{spec.unit}]" if spec.unit else "")
    if spec.range is not None:
        kind += f" {spec.range[0]:g}…{spec.range[1]:g}"
    if getattr(spec, "values", None):
        kind += " one of " + ", ".join(f'"{v}"' for v in spec.values)
    source = f"  ({spec.provider})" if spec.provider else ""
    return f"{spec.name:<20} {kind:<24} {spec.doc}{source}"


def _answers(app: str):
    from applications.appfolder import DIALOG_FILE, answer_declarations
    from applications.database import DatabaseContent
    from applications.dialog import check_dialog
    from applications.graph.loader import find_application

    folder = find_application(app)
    content = DatabaseContent(folder)
    dialog, _ = check_dialog(folder / DIALOG_FILE, choices=content.choices if content.usable else None)
    answers = [spec for name, spec in answer_declarations(dialog).items()
               if name != "dialog.answer"]
    return answers + list(_parameters(app).values())


def _parameters(app: str) -> dict:
    """The application's parameters (param.<name>), as declared in its graph.xml."""
    from applications.appfolder import inspect_folder
    draft, _, _ = inspect_folder(app)
    return dict(draft.params) if draft is not None else {}
