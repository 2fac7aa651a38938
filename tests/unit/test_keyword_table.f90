!> Keyword names: first token only, case, options _TITLE and _ID, aliases,
!> width suffixes, skip list and unknown keywords.
program test_keyword_table
    use xd_testing, only: check, test_summary
    use xd_input_field_reader, only: width_standard, width_long, width_i10
    use xd_input_keyword_table, only: keyword_t, lookup_keyword, fam_geometry, fam_material, fam_set, &
                                      fam_condition, fam_skip, fam_unknown, fam_planned, fam_contact, fam_meta, &
                                      fam_database, fam_control
    implicit none
    type(keyword_t) :: kw
    call look('*ELEMENT_SOLID (ten nodes format)')
    call check(kw%name == 'ELEMENT_SOLID' .and. kw%family == fam_geometry, 'only the first token is the keyword')
    call look('*node')
    call check(kw%name == 'NODE', 'keywords are case-insensitive')
    call look('*MAT_001_TITLE')
    call check(kw%name == 'MAT_ELASTIC' .and. kw%title .and. kw%family == fam_material, 'alias with _TITLE')
    call look('*SET_NODE_TITLE')
    call check(kw%name == 'SET_NODE_LIST' .and. kw%title .and. kw%family == fam_set, '*SET_NODE is *SET_NODE_LIST')
    call look('*SET_NODE_LIST_GENERATE')
    call check(kw%name == 'SET_NODE_LIST_GENERATE' .and. .not. kw%title, '_GENERATE is its own keyword')
    call look('*BOUNDARY_SPC_SET_ID')
    call check(kw%name == 'BOUNDARY_SPC_SET' .and. kw%has_id .and. kw%family == fam_condition, '_ID option')
    call look('*MAT_ELASTIC_ID')
    call check(kw%family == fam_unknown, '_ID only where the keyword takes it')
    call look('*NODE +')
    call check(kw%width_mode == width_long, '*NODE + is long format')
    call look('*NODE%')
    call check(kw%name == 'NODE' .and. kw%width_mode == width_i10, '*NODE% is I10 format')
    call lookup_keyword('*NODE-', width_long, kw)
    call check(kw%width_mode == width_standard, '*NODE- is standard format in a LONG deck')
    call lookup_keyword('*PART', width_long, kw)
    call check(kw%width_mode == width_long, 'a keyword without suffix inherits the deck format')
    call look('*CONTROL_MPP_IO_NOD3DUMP')
    call check(kw%family == fam_skip, 'prefix entries of the skip list (*CONTROL_MPP_*)')
    call look('*SET_SOLID_GENERAL_TITLE')
    call check(kw%family == fam_planned, 'keywords for later work are told apart from unknown ones')
    call look('*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID')
    call check(kw%family == fam_contact .and. kw%has_id .and. kw%name == 'CONTACT_AUTOMATIC_SINGLE_SURFACE', &
               'contact keywords take the _ID option')
    call look('*KEYWORD_ID')
    call check(kw%family == fam_meta .and. kw%name == 'KEYWORD_ID', '*KEYWORD_ID is read (it stopped decks at line 1)')
    call look('*CONTROL_ACCURACY')
    call check(kw%family == fam_control, '*CONTROL_ACCURACY is read (its fields are checked and named)')
    call look('*DATABASE_ABSTAT')
    call check(kw%family == fam_skip, 'an output request xdyna does not write is skipped with a warning')
    call look('*DATABASE_HISTORY_NODE_ID')
    call check(kw%family == fam_database .and. kw%name == 'DATABASE_HISTORY_NODE_ID', &
               '*DATABASE_HISTORY_NODE_ID is read, not taken by the output pattern')
    call look('*CONTACT_AUTOMATIC_GENERAL_ID')
    call check(kw%family == fam_contact .and. kw%has_id, 'the patterns come after exact names and their _ID forms')
    call look('*DATABASE_BINARY_D3PLOT')
    call check(kw%family == fam_database, 'an output xdyna writes is read, not skipped')
    call look('*WHATEVER')
    call check(kw%family == fam_unknown .and. kw%name == 'WHATEVER', 'unknown keyword')
    call test_summary()
contains
    subroutine look(text)
        character(len=*), intent(in) :: text
        kw = keyword_t()
        call lookup_keyword(text, width_standard, kw)
    end subroutine look
end program test_keyword_table
