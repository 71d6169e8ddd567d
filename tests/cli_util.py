"""Running the command line in-process, as the tests of every command group do."""
from kapitza.cli import main


def run(argv, capsys):
    """(exit status, stdout, stderr) of ``kapitza argv``; argparse errors exit via SystemExit."""
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, err, *needles):
    """Status 2, exactly one line on stderr, no traceback, and each needle in that line."""
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("kapitza"), lines[0]
    for n in needles:
        assert n in lines[0], (n, lines[0])
