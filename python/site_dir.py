"""The folder under an install prefix where that prefix's Python finds modules.

    python3 site_dir.py PREFIX

- Debian's /usr and /usr/local: the dist-packages folder Debian's Python reads there.
- A prefix with its own interpreter (a virtual environment, or a Python installed there):
  that interpreter's site-packages.
- Any other prefix: PREFIX/lib/pythonX.Y/site-packages, which Python reads once it is on
  PYTHONPATH (the install says so).
"""
import os
import subprocess
import sys
import sysconfig

prefix = os.path.abspath(sys.argv[1])
own = os.path.join(prefix, "bin", "python3")
if prefix == "/usr" and "deb_system" in sysconfig.get_scheme_names():
    print(sysconfig.get_path("platlib", "deb_system"))
elif prefix == "/usr/local" and sysconfig.get_default_scheme() == "posix_local":
    print(sysconfig.get_path("platlib", "posix_local"))
elif os.path.isfile(own) and os.access(own, os.X_OK):
    print(subprocess.check_output(
        [own, "-c", "import sysconfig; print(sysconfig.get_path('platlib'))"],
        text=True).strip())
else:
    print(sysconfig.get_path("platlib", "posix_prefix",
                             vars={"base": prefix, "platbase": prefix}))
