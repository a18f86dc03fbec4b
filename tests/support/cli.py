"""Running the command line inside a test."""

from placement.cli import main


def run_command(argv: list[str], capsys) -> tuple[int, str, str]:
    """Exit code, standard output and standard error of the command line (argparse's own errors exit through
    SystemExit); never a traceback."""
    try:
        code = main(argv)
    except SystemExit as exit_:
        code = exit_.code
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    return code, captured.out, captured.err
