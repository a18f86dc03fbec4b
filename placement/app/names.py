"""Accessible names for the page's controls: what a screen reader says for each field, slider and icon button.

viser's page (1.1) labels a field with a ``<label for=...>`` naming viser's id, not the input's, so
no input is named by its label, and its slider and icon buttons carry no name at all. A script run in
each tab when it connects names every unnamed control after the label in its row (``x (mm)``, ``time
(s)``), or after its icon (``close``, ``viewer settings``), and names the controls the page adds later
(a folder unfolded, a panel redrawn) as they appear.
"""

from __future__ import annotations

import viser  # optional dependency: the [app] extra, checked by placement.app

from placement.app.shown import run_script

ICON_NAMES = {"x": "close", "adjustments": "viewer settings", "minus": "fold the panel", "plus": "unfold the panel"}
SCRIPT = """(() => {
  if (window.placementNames) return;
  window.placementNames = true;
  const icons = ICONS;
  const unnamed = (control) => !(control.getAttribute("aria-label") || "").trim();
  const controls = "input:not([type=hidden]), textarea, [role=slider]";
  const nameAll = () => {
    for (const label of document.querySelectorAll("label[for]")) {
      let box = label;
      while (box !== null && box.querySelector(controls) === null) box = box.parentElement;
      if (box === null) continue;
      for (const control of box.querySelectorAll(controls))
        if (unnamed(control)) control.setAttribute("aria-label", label.textContent.trim());
    }
    for (const button of document.querySelectorAll("button:not([hidden])")) {
      if (button.textContent.trim() || !unnamed(button)) continue;
      const icon = [...(button.querySelector("svg")?.classList ?? [])].find((name) => name.startsWith("tabler-icon-"));
      const key = icon === undefined ? "" : icon.slice("tabler-icon-".length);
      const name = icons[key] ?? (button.closest(".mantine-Notification-root") ? "close" : key.replaceAll("-", " "));
      if (name) button.setAttribute("aria-label", name);
    }
  };
  nameAll();
  new MutationObserver(nameAll).observe(document.body, {childList: true, subtree: true});
})();"""


def name_controls(client: viser.ClientHandle) -> None:
    """Give every control of a tab's page an accessible name, now and as the page adds controls."""
    import json

    run_script(client, SCRIPT.replace("ICONS", json.dumps(ICON_NAMES)))
