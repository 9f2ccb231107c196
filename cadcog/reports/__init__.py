"""What people read: self-contained HTML pages, figures (matplotlib, imported only when asked)
and JUnit XML. Reports call the layers below; nothing below imports them.
"""
