"""The workbench: the placement of one path on one robot, live in the browser (``python -m placement app``)."""
