"""What an export could not represent, gathered so the engine reports it once per render."""


class ExportLog:
    def __init__(self):
        self.unsupported = {}   # description -> [names of the data-blocks concerned]
        self.problems = []      # scene problems that are not missing features (zero-size light, ...)

    def unsupported_feature(self, what, owner=""):
        owners = self.unsupported.setdefault(what, [])
        if owner and owner not in owners:
            owners.append(owner)

    def problem(self, text):
        if text not in self.problems:
            self.problems.append(text)

    def warning_text(self):
        """One line naming everything that was ignored or approximated; '' when nothing was."""
        parts = []
        for what, owners in self.unsupported.items():
            shown = ", ".join(owners[:4]) + (f" +{len(owners) - 4} more" if len(owners) > 4 else "")
            parts.append(f"{what} ({shown})" if shown else what)
        text = ""
        if parts:
            text = "SPHRECT does not support, ignored: " + "; ".join(parts)
        if self.problems:
            text = (text + ". " if text else "") + "Scene problems: " + "; ".join(self.problems)
        return text
