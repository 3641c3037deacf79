"""Atomic file writing: a temporary file in the same folder, then a rename."""

import os
import tempfile


def write_atomic(path, content, mode="w"):
    """Writes `content` (str, or bytes with mode "wb") to `path` atomically."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".partial", dir=folder)
    try:
        with os.fdopen(fd, mode) as fh:
            fh.write(content)
            fh.flush()
            os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the usual file mode
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_csv_atomic(df, path, **kwargs):
    """pandas DataFrame -> CSV, atomically (full round-trip precision)."""
    kwargs.setdefault("index", False)
    kwargs.setdefault("float_format", "%.17g")
    write_atomic(path, df.to_csv(**kwargs))


def save_figure_atomic(fig, path, dpi=120):
    """Saves a matplotlib figure atomically (PNG)."""
    import io
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    write_atomic(path, buf.getvalue(), mode="wb")
