!> The deck as a list of lines in reading order: files loaded whole, `*INCLUDE`
!> expanded in place, `*END` honoured per file, every line tagged with its
!> file and line number for error messages. Under MPI rank 0 alone opens
!> the files (the deck and its includes) and every rank takes their text
!> from it (read_whole, find_include): one process reads a deck on a
!> cluster's shared file system, and a deck only rank 0 can see (a local
!> disk of its node) runs; before, every rank read every file, and a rank
!> that could not stopped the run in a hang.
module xd_input_deck_source
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: to_upper, dirname, join_path, itoa
    use xd_core_memory, only: grow
    use xd_core_files, only: file_kind, fk_directory, fk_other
    use xd_core_comm, only: comm_rank_size, comm_bcast_text
    implicit none
    private
    public :: deck_source_t, load_deck, max_include_depth

    integer, parameter :: max_include_depth = 32

    type :: file_text_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: text
    end type file_text_t

    type :: deck_source_t
        integer :: nfile = 0
        type(file_text_t), allocatable :: files(:)
        integer :: nline = 0
        integer, allocatable :: lfile(:)    !< file index of line
        integer, allocatable :: lstart(:)   !< first character in that file's text
        integer, allocatable :: llen(:)     !< length without the newline
        integer, allocatable :: lnum(:)     !< line number in its file
        integer :: ndir = 0                 !< *INCLUDE_PATH directories
        type(file_text_t), allocatable :: dirs(:)
    contains
        procedure :: line => source_line
        procedure :: where => source_where
        procedure :: file_of => source_file_of
        procedure :: is_comment => source_is_comment
        procedure :: is_keyword => source_is_keyword
        procedure :: digest => source_digest
        procedure :: release => source_release
    end type deck_source_t

contains

    !> Load `path` and every file it includes.
    subroutine load_deck(src, path, error)
        type(deck_source_t), intent(out) :: src
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: error
        allocate (src%files(8))
        call load_file(src, path, 0, 0, 0, error)
    end subroutine load_deck

    recursive subroutine load_file(src, path, depth, from_file, from_line, error)
        type(deck_source_t), intent(inout) :: src
        character(len=*), intent(in) :: path
        integer, intent(in) :: depth, from_file, from_line
        type(error_t), allocatable, intent(out) :: error
        integer :: ifile, pos, n, lineno, eol, k, nincl
        character(len=:), allocatable :: word, fname, why

        if (depth > max_include_depth) then
            call make_error(error, '*INCLUDE nested more than '//itoa(max_include_depth)// &
                            ' deep (an include cycle?)', src%files(from_file)%name, from_line)
            return
        end if
        call add_file(src, path, ifile)
        call read_whole(src%files(ifile)%text, path, n, error)
        if (allocated(error)) then
            why = error%message
            if (from_file > 0) then
                call make_error(error, '*INCLUDE: cannot open '''//path//''' ('//why//')', &
                                src%files(from_file)%name, from_line)
            else
                call make_error(error, 'cannot open deck '''//path//''' ('//why//')')
            end if
            return
        end if

        pos = 1
        lineno = 0
        do while (pos <= n)
            call line_bounds(src%files(ifile)%text, pos, k, eol)
            lineno = lineno + 1
            call add_line(src, ifile, pos, k - pos + 1, lineno)
            pos = eol + 1
            if (.not. src%is_keyword(src%nline)) cycle
            word = first_token(src%line(src%nline))
            if (word == '*END') then
                src%nline = src%nline - 1
                exit
            end if
            if (word /= '*INCLUDE' .and. word /= '*INCLUDE_PATH' .and. word /= '*INCLUDE_PATH_RELATIVE') cycle
            ! *INCLUDE: every card up to the next keyword is a file name (one
            ! per card, as LS-DYNA allows), ' +' at its end continues it on the
            ! next card. *INCLUDE_PATH(_RELATIVE): each card a directory where
            ! included files are looked for (relative: to the main deck's).
            src%nline = src%nline - 1
            nincl = 0
            do while (pos <= n)
                if (src%files(ifile)%text(pos:pos) == '*') exit
                call next_name(src%files(ifile)%text, pos, lineno, fname)
                if (len(fname) == 0) cycle
                if (word == '*INCLUDE_PATH') then
                    call add_search_dir(src, join_path(dirname(path), fname))
                else if (word == '*INCLUDE_PATH_RELATIVE') then
                    call add_search_dir(src, join_path(dirname(src%files(1)%name), fname))
                else
                    call load_file(src, find_include(src, dirname(path), fname), depth + 1, ifile, lineno, error)
                    if (allocated(error)) return
                    nincl = nincl + 1
                end if
            end do
            if (word == '*INCLUDE' .and. nincl == 0) then
                call make_error(error, '*INCLUDE card 1 field FILENAME: no file name given', &
                                src%files(ifile)%name, lineno)
                return
            end if
        end do
    end subroutine load_file

    !> The file or directory name that starts at `pos` in `text`: comment
    !> cards skipped, ' +' at a card's end continuing it on the next, up to
    !> the next keyword; pos and lineno move past it ('' if none).
    subroutine next_name(text, pos, lineno, fname)
        character(len=*), intent(in) :: text
        integer, intent(inout) :: pos, lineno
        character(len=:), allocatable, intent(out) :: fname
        character(len=:), allocatable :: cont
        integer :: k, eol, j
        logical :: more
        fname = ''
        more = .true.
        do while (more .and. pos <= len(text))
            if (text(pos:pos) == '*') exit
            call line_bounds(text, pos, k, eol)
            lineno = lineno + 1
            cont = text(pos:k)
            pos = eol + 1
            if (len(cont) > 0) then
                if (cont(1:1) == '$') cycle
            end if
            j = len_trim(cont)
            more = .false.
            if (j >= 2) then
                if (cont(j - 1:j) == ' +') then
                    more = .true.
                    j = j - 2
                end if
            end if
            fname = fname//trim(adjustl(cont(1:j)))
        end do
    end subroutine next_name

    subroutine add_search_dir(src, dir)
        type(deck_source_t), intent(inout) :: src
        character(len=*), intent(in) :: dir
        type(file_text_t), allocatable :: tmp(:)
        if (.not. allocated(src%dirs)) allocate (src%dirs(4))
        if (src%ndir == size(src%dirs)) then
            allocate (tmp(2*src%ndir))
            tmp(1:src%ndir) = src%dirs(1:src%ndir)
            call move_alloc(tmp, src%dirs)
        end if
        src%ndir = src%ndir + 1
        src%dirs(src%ndir)%name = dir
    end subroutine add_search_dir

    !> An included file: next to the including file, else in the
    !> *INCLUDE_PATH directories in the order given; the first place if none
    !> has it (the open then fails naming it).
    function find_include(src, here, fname) result(p)
        type(deck_source_t), intent(in) :: src
        character(len=*), intent(in) :: here, fname
        character(len=:), allocatable :: p
        logical :: there
        integer :: i, rank, nranks
        p = join_path(here, fname)
        ! (under MPI rank 0 looks, and every rank takes its choice: the
        ! files are read by it, read_whole)
        call comm_rank_size(rank, nranks)
        if (rank == 0) call look()
        if (nranks > 1) call comm_bcast_text(p)
    contains
        subroutine look()
            inquire (file=p, exist=there)
            if (there) return
            do i = 1, src%ndir
                inquire (file=join_path(src%dirs(i)%name, fname), exist=there)
                if (there) then
                    p = join_path(src%dirs(i)%name, fname)
                    return
                end if
            end do
        end subroutine look
    end function find_include

    !> The line that starts at `pos`: its last character `last` (a carriage
    !> return before the newline is dropped) and the position `eol` of its
    !> newline (len(text) + 1 for a last line without one).
    pure subroutine line_bounds(text, pos, last, eol)
        character(len=*), intent(in) :: text
        integer, intent(in) :: pos
        integer, intent(out) :: last, eol
        ! (a loop over the characters: the library's index() took 700
        ! instructions a line of a large deck)
        do eol = pos, len(text)
            if (iachar(text(eol:eol)) == 10) exit
        end do
        last = eol - 1
        if (last >= pos) then
            if (text(last:last) == achar(13)) last = last - 1
        end if
    end subroutine line_bounds

    subroutine add_file(src, path, ifile)
        type(deck_source_t), intent(inout) :: src
        character(len=*), intent(in) :: path
        integer, intent(out) :: ifile
        type(file_text_t), allocatable :: tmp(:)
        if (src%nfile == size(src%files)) then
            allocate (tmp(2*size(src%files)))
            tmp(1:src%nfile) = src%files(1:src%nfile)
            call move_alloc(tmp, src%files)
        end if
        src%nfile = src%nfile + 1
        ifile = src%nfile
        src%files(ifile)%name = path
    end subroutine add_file

    subroutine add_line(src, ifile, start, length, lineno)
        type(deck_source_t), intent(inout) :: src
        integer, intent(in) :: ifile, start, length, lineno
        integer :: i
        i = src%nline + 1
        call grow(src%lfile, i, 'deck line table')
        call grow(src%lstart, i, 'deck line table')
        call grow(src%llen, i, 'deck line table')
        call grow(src%lnum, i, 'deck line table')
        src%lfile(i) = ifile
        src%lstart(i) = start
        src%llen(i) = max(length, 0)
        src%lnum(i) = lineno
        src%nline = i
    end subroutine add_line

    subroutine read_whole(text, path, n, error)
        character(len=:), allocatable, intent(out) :: text
        character(len=*), intent(in) :: path
        integer, intent(out) :: n
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: why
        integer :: rank, nranks
        call comm_rank_size(rank, nranks)
        if (nranks <= 1) then
            call read_file(text, path, n, error)
            return
        end if
        ! (under MPI rank 0 reads the file for every rank, which takes its
        ! text, or the reason it could not, from it: one process opens a
        ! deck on a cluster's shared file system, not every rank)
        why = ''
        if (rank == 0) then
            call read_file(text, path, n, error)
            if (allocated(error)) why = error%message
        end if
        call comm_bcast_text(why)
        if (len(why) > 0) then
            if (rank /= 0) call make_error(error, why)
            n = 0
            return
        end if
        if (.not. allocated(text)) allocate (character(len=0) :: text)
        call comm_bcast_text(text)
        n = len(text)
    end subroutine read_whole

    !> The whole of the regular file at path (n characters).
    subroutine read_file(text, path, n, error)
        character(len=:), allocatable, intent(out) :: text
        character(len=*), intent(in) :: path
        integer, intent(out) :: n
        type(error_t), allocatable, intent(out) :: error
        integer :: u, st
        logical :: there
        inquire (file=path, exist=there)
        n = 0
        if (.not. there) then
            call make_error(error, 'no such file')
            return
        end if
        ! a FIFO would block the reader for ever, a device (/dev/zero) has
        ! no size to read: only regular files are decks
        select case (file_kind(path))
        case (fk_directory)
            call make_error(error, 'it is a directory, not a file')
            return
        case (fk_other)
            call make_error(error, 'it is not a regular file (a FIFO, a device or a socket)')
            return
        end select
        open (newunit=u, file=path, access='stream', form='unformatted', status='old', &
              action='read', iostat=st)
        if (st /= 0) then
            call make_error(error, 'cannot open')
            return
        end if
        inquire (unit=u, size=n)
        allocate (character(len=max(n, 0)) :: text)
        if (n > 0) read (u, iostat=st) text
        close (u)
        if (st /= 0) call make_error(error, 'cannot read')
    end subroutine read_file

    pure function first_token(s) result(w)
        character(len=*), intent(in) :: s
        character(len=:), allocatable :: w
        integer :: k
        k = index(s, ' ')
        if (k == 0) then
            w = to_upper(s)
        else
            w = to_upper(s(1:k - 1))
        end if
    end function first_token

    function source_line(self, i) result(s)
        class(deck_source_t), intent(in) :: self
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        s = self%files(self%lfile(i))%text(self%lstart(i):self%lstart(i) + self%llen(i) - 1)
    end function source_line

    !> `file:line` of line i, for messages.
    function source_where(self, i) result(s)
        class(deck_source_t), intent(in) :: self
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        s = self%files(self%lfile(i))%name//':'//itoa(self%lnum(i))
    end function source_where

    function source_file_of(self, i) result(s)
        class(deck_source_t), intent(in) :: self
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        s = self%files(self%lfile(i))%name
    end function source_file_of

    logical function source_is_comment(self, i)
        class(deck_source_t), intent(in) :: self
        integer, intent(in) :: i
        source_is_comment = .false.
        if (self%llen(i) > 0) source_is_comment = self%files(self%lfile(i))%text(self%lstart(i):self%lstart(i)) == '$'
    end function source_is_comment

    logical function source_is_keyword(self, i)
        class(deck_source_t), intent(in) :: self
        integer, intent(in) :: i
        source_is_keyword = .false.
        if (self%llen(i) > 0) source_is_keyword = self%files(self%lfile(i))%text(self%lstart(i):self%lstart(i)) == '*'
    end function source_is_keyword

    !> A fingerprint of the deck's text, every file in reading order: its
    !> length and FNV-1a (32 bits) of its characters, as 'length-hash'. A
    !> restart compares it with the dump's to refuse a changed deck.
    function source_digest(src) result(d)
        class(deck_source_t), intent(in) :: src
        character(len=:), allocatable :: d
        integer, parameter :: i8 = selected_int_kind(18)
        integer(i8) :: h, n
        integer(i8), parameter :: prime = 16777619_i8, mask = 4294967295_i8
        integer :: f, k
        character(len=40) :: buf
        h = 2166136261_i8
        n = 0
        do f = 1, src%nfile
            do k = 1, len(src%files(f)%text)
                h = iand(ieor(h, int(ichar(src%files(f)%text(k:k)), i8))*prime, mask)
            end do
            n = n + len(src%files(f)%text)
        end do
        write (buf, '(i0,a,z8.8)') n, '-', h
        d = trim(buf)
    end function source_digest

    !> The deck's text and line tables freed once the model is read (every
    !> MPI rank holds the deck's text, read by rank 0: the 120,000-shell
    !> tubes' 15 MB each); the file names stay.
    subroutine source_release(src)
        class(deck_source_t), intent(inout) :: src
        integer :: k
        if (allocated(src%files)) then
            do k = 1, size(src%files)
                if (allocated(src%files(k)%text)) deallocate (src%files(k)%text)
            end do
        end if
        if (allocated(src%lfile)) deallocate (src%lfile, src%lstart, src%llen, src%lnum)
        src%nline = 0
    end subroutine source_release

end module xd_input_deck_source
