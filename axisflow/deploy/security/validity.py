"""How long a certificate is valid: from :data:`CLOCK_SKEW` before it is issued, for a number of days in
1…:data:`MAX_DAYS` (:data:`DEFAULT_DAYS` unless asked), checked before anything is issued. No
cryptography here: the command line offers the default before it loads :mod:`.certificates`."""

from __future__ import annotations

import datetime as dt

from .errors import SecurityArgumentError

DEFAULT_DAYS = 365
MAX_DAYS = 3650
CLOCK_SKEW = dt.timedelta(minutes=5)
"""certificates are valid from this long before they are issued (hosts whose clocks lag a little)"""


def check_days(days: int) -> None:
    """A validity in 1…:data:`MAX_DAYS` days; else a :class:`SecurityArgumentError`."""
    if not 1 <= days <= MAX_DAYS:
        raise SecurityArgumentError(f"validity = {days} days must be in 1…{MAX_DAYS} days")
