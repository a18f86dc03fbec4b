"""What users read and see: text reports and JSON (:mod:`placement.output.report`), plots
(:mod:`placement.output.plots`) and the 3-D scene (:mod:`placement.output.scene`)."""
