"""The exceptions of the hapticd package. Each carries the server's (or the session loader's) message."""


class Error(RuntimeError):
    """Base class of the package's errors."""


class SessionError(Error):
    """A session cannot be built, stepped or stopped. A configuration error names the file (or the override),
    the line and the key: "session.yaml:12: devices[0].virtual_model.parameters.mass_kg: ..."."""


class RequestRefused(Error):
    """The server (or the in-process session) refused a request; the message says why."""


class ClaimLost(Error):
    """The engine's claim of the device ended without its release: the server found the engine gone for longer
    than its claim hold (docs/safety.md, "Ownership"). Its commands are no longer taken; claim again or stop."""


class Timeout(Error, TimeoutError):
    """No reply, device or state within the timeout."""
