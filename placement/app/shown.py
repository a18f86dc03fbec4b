"""The texts a tab's fields show, read from the tab itself: what the workbench acts on is what the user sees.

viser's page (1.1) sends every GUI message of its panel through one sender that passes one message per 50 ms
and keeps only the latest one waiting (``makeThrottledMessageSender`` in its client). A field's last keys
and the Enter, the click or the next field's keys that follow them within 50 ms reach the server as that
Enter, click or key alone: the server would hold ``-2`` while the page shows ``-20``, and no later message
brings the lost text back. Enter or a click cannot carry the text either (viser's form submission names
the form, not its values).

So before it acts on typed text, the workbench asks the tab that acted what its fields show, through a
channel that passes that sender by: a short script (viser's ``RunJavascriptMessage``, which its Plotly
support uses) copies the fields' texts into the tab's ``localStorage`` under a one-time key, and viser's
``localStorage`` read (:meth:`viser.LocalStorageHandle.get_item`, answered at once, unthrottled, after the
script since a tab's messages are handled in order) brings them back. Each field the server held behind
is set to the text shown, so the actions, and every other tab, read what the user typed.

viser offers no public way to run a script in one tab, so :func:`run_script` uses its message type and the
client's connection; :func:`check_viser` refuses to start a workbench on a viser without them (fails closed),
and the browser tests type whole values and Enter within one millisecond.
"""

from __future__ import annotations

import json
import logging
import secrets
from typing import Any

import viser  # optional dependency: the [app] extra, checked by placement.app

LOG = logging.getLogger("placement.app")
ANSWER_TIMEOUT_S = 5.0  # a tab answers in milliseconds; one that does not within this is not read
SCRIPT = """(() => {
  const key = Object.keys(localStorage).find((name) => name.endsWith(KEY));
  if (key === undefined) return;
  const shown = {};
  for (const uuid of UUIDS) {
    let box = document.querySelector(`label[for="${CSS.escape(uuid)}"]`);
    while (box !== null && box.querySelector("input, textarea") === null) box = box.parentElement;
    if (box !== null) shown[uuid] = box.querySelector("input, textarea").value;
  }
  localStorage.setItem(key, JSON.stringify(shown));
})();"""


def check_viser() -> None:
    """Refuse a viser without the means the fields are read by.

    Raises:
        RuntimeError: viser's script message or a client's localStorage is not where this module uses them
            (as :func:`placement.app.guard.guarded_server` refuses a viser it cannot guard).
    """
    from viser import _messages  # viser's own message types: no public way to run a script in one tab

    if not hasattr(_messages, "RunJavascriptMessage") or not hasattr(getattr(viser, "LocalStorageHandle", None), "get_item"):
        raise RuntimeError(f"the workbench cannot read what its fields show with viser {viser.__version__}: not served")


def run_script(client: viser.ClientHandle, source: str) -> None:
    """Run a script in one tab (viser's own message, checked by :func:`check_viser`)."""
    from viser import _messages

    client._websock_connection.queue_message(_messages.RunJavascriptMessage(source=source))


class ShownTexts:
    """The text fields whose texts are read from the tab that acts (see the module's text)."""

    def __init__(self) -> None:
        self.fields: dict[str, Any] = {}  # text handles (whose values the workbench sets) by viser's id: their labels' ``for``

    def watch(self, *fields: viser.GuiTextHandle) -> None:
        """Read these fields too."""
        for field in fields:
            self.fields[field._impl.uuid] = field

    def catch_up(self, client: Any) -> tuple[str, ...]:
        """Set each field to the text ``client``'s tab shows; a tab that cannot be read is logged and its fields
        keep the server's texts (the Exact panel says the placement it evaluated).

        Args:
            client: The tab that acted (a :class:`viser.ClientHandle`; None: the server itself acted).

        Returns:
            The labels of the fields whose text the server held behind the tab's.
        """
        if not isinstance(client, viser.ClientHandle) or not self.fields:
            return ()
        key = f"placement-shown-{secrets.token_hex(12)}"
        storage = client.local_storage
        storage.set_item(key, "")
        run_script(client, SCRIPT.replace("KEY", json.dumps(key)).replace("UUIDS", json.dumps(list(self.fields))))
        try:
            answer = storage.get_item(key, timeout=ANSWER_TIMEOUT_S)
        except (RuntimeError, TimeoutError) as error:
            LOG.warning("workbench: could not read the fields a tab shows: %s", " ".join(str(error).split())[:200])
            return ()
        finally:
            storage.remove_item(key)
        shown = json.loads(answer) if answer else None
        if not isinstance(shown, dict):
            LOG.warning("workbench: a tab did not say what its fields show (its page may not be viser 1.1's)")
            return ()
        behind = []
        for uuid, text in shown.items():
            field = self.fields.get(uuid)
            if field is not None and isinstance(text, str) and field.value != text:
                field.value = text
                behind.append(field.label)
        return tuple(behind)
