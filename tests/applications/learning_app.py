"""A copy of the bundled survey whose CreateAttention state offers alternatives (issue 27),
for the tests of choice points, the learner and campaigns."""
from __future__ import annotations

import shutil
from pathlib import Path

from applications.graph.loader import find_application

OVERRIDE = ('<override state="CreateAttention" when="user.distance > 2.5m" '
            'behavior="AttractAttention"/>')
CHOICE = """<choice id="attract" state="CreateAttention" by="{by}"{context}>
    <alternative id="face" behavior="FaceUser"/>
    <alternative id="call" behavior="AttractAttention">
      <say>Hi! Over here, please!</say>
      <say xml:lang="de">Hallo! Hier herüber, bitte!</say>
    </alternative>
    <success when='state == "Interaction"' within="15s"/>
  </choice>"""


def survey_with_choice(folder: Path, by: str = "learn", context: str | None = None,
                       choice: str | None = None) -> Path:
    """The survey in `folder`, its override replaced by a choice point (or by `choice`)."""
    shutil.copytree(find_application("survey"), folder)
    dialog = folder / "dialog.xml"
    text = choice if choice is not None else CHOICE.format(
        by=by, context=f' context="{context}"' if context else "")
    dialog.write_text(dialog.read_text().replace(OVERRIDE, text))
    return folder
