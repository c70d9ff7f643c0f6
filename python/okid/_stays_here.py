# SPDX-License-Identifier: Apache-2.0
"""StaysHere: the base of the streaming identifiers, whose C core (the pushed samples or sums) lives
in this process: copy, deepcopy and pickle raise TypeError saying what to do instead; a context
manager whose exit calls the subclass's close()."""
from typing import Any, Dict, NoReturn, Tuple, TypeVar

_T = TypeVar("_T", bound="StaysHere")


class StaysHere:
    #: what the core holds and what to do instead: (held, instead), set by each subclass
    _HOLDS: Tuple[str, str] = ("", "")

    def __copy__(self) -> NoReturn:
        held, instead = self._HOLDS
        raise TypeError(f"an okid.{type(self).__name__} cannot be copied: the copy would share its C core ({held}); "
                        f"create another {type(self).__name__} and push the same samples into it")

    def __deepcopy__(self, memo: Dict[int, Any]) -> NoReturn:
        self.__copy__()

    def __reduce__(self) -> NoReturn:
        held, instead = self._HOLDS
        raise TypeError(f"an okid.{type(self).__name__} cannot be pickled: its C core ({held}) stays in this "
                        f"process; {instead}")

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self: _T) -> _T:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
