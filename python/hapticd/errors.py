"""The exceptions of the hapticd package. Each carries the server's (or the session loader's) message."""


class Error(RuntimeError):
    """Base class of the package's errors."""


class SessionError(Error):
    """A session cannot be built, stepped or stopped. A configuration error names the file (or the override),
    the line and the key: "session.yaml:12: devices[0].virtual_model.parameters.mass_kg: ..."."""


class RequestRefused(Error):
    """The server (or the in-process session) refused a request; the message says why."""


class Timeout(Error, TimeoutError):
    """No reply, device or state within the timeout."""
